//! The `crowdgaze` command-line tool, run as a program: the demo and its pictures,
//! annotation of the real ETH and UCY trajectories, BVH round trips and gaze added to a real
//! clip, plots, and bad input (one clear line naming file and line, non-zero exit, no
//! output file left behind).

use std::collections::{BTreeSet, HashMap};
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use crowdgaze_cli::bvh::Bvh;
use crowdgaze_cli::skeleton::global_rotation;
use glam::DVec3;

fn crowdgaze(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_crowdgaze"))
        .args(args)
        .output()
        .expect("run crowdgaze")
}

fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

fn succeed(args: &[&str]) -> String {
    let output = crowdgaze(args);
    assert!(
        output.status.success(),
        "crowdgaze {args:?} failed: {}{}",
        text(&output.stdout),
        text(&output.stderr)
    );
    text(&output.stdout)
}

/// A file of the shared data directory (`../shared/data` from the repository); fails if it
/// is missing.
fn data(relative: &str) -> PathBuf {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../shared/data")
        .join(relative);
    assert!(
        path.exists(),
        "{} is missing: the tests need ../shared/data beside the repository",
        path.display()
    );
    path
}

fn entries(directory: &Path) -> BTreeSet<String> {
    std::fs::read_dir(directory)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect()
}

fn check_png(path: &Path) {
    let bytes = std::fs::read(path).unwrap();
    assert!(
        bytes.starts_with(b"\x89PNG\r\n\x1a\n"),
        "{} is not a PNG",
        path.display()
    );
    let decoder = png::Decoder::new(std::io::Cursor::new(bytes));
    let mut reader = decoder.read_info().expect("PNG header");
    let (width, height) = (reader.info().width, reader.info().height);
    assert!(width >= 400 && height >= 200, "{width}x{height}");
    let mut pixels = vec![0; reader.output_buffer_size().expect("size")];
    let frame = reader.next_frame(&mut pixels).expect("PNG data");
    let pixels = &pixels[..frame.buffer_size()];
    // Not blank: more than a handful of distinct colours.
    let colours: BTreeSet<&[u8]> = pixels.chunks(3).collect();
    assert!(colours.len() > 5, "{} looks blank", path.display());
}

fn check_svg(path: &Path) {
    let svg = std::fs::read_to_string(path).unwrap();
    let document = roxmltree::Document::parse(&svg)
        .unwrap_or_else(|e| panic!("{} is not XML: {e}", path.display()));
    assert_eq!(document.root_element().tag_name().name(), "svg");
    let drawing = document
        .descendants()
        .filter(|n| {
            matches!(
                n.tag_name().name(),
                "line" | "polyline" | "path" | "rect" | "circle" | "text" | "polygon"
            )
        })
        .count();
    assert!(
        drawing > 20,
        "{} has {drawing} drawing elements",
        path.display()
    );
}

#[test]
fn demo_prints_a_summary_and_writes_valid_pictures() {
    let directory = tempfile::tempdir().unwrap();
    let out = directory.path().join("demo");
    let stdout = succeed(&[
        "demo",
        "--seconds",
        "3",
        "--seed",
        "7",
        "--out",
        out.to_str().unwrap(),
    ]);
    println!("{stdout}");
    for needle in ["attentive:", "gaze shifts:", "µs per character-frame"] {
        assert!(stdout.contains(needle), "no '{needle}' in {stdout}");
    }
    // The street has standing groups that talk in turns: about a sixth of its 130 people in
    // groups of two and three.
    let groups = stdout
        .lines()
        .find_map(|l| l.trim().strip_prefix("groups:"))
        .unwrap_or_else(|| panic!("no groups line in {stdout}"));
    let numbers: Vec<usize> = groups
        .split(|c: char| !c.is_ascii_digit())
        .filter_map(|w| w.parse().ok())
        .collect();
    let (count, people) = (numbers[0], numbers[1]);
    assert!(
        (2 * count..=3 * count).contains(&people) && (18..=26).contains(&people),
        "{groups}"
    );
    assert!(groups.contains("talking in turns"), "{groups}");
    assert!(groups.contains("listeners look at the speaker"), "{groups}");
    let files = entries(&out);
    let pngs: Vec<&String> = files.iter().filter(|f| f.ends_with(".png")).collect();
    let svgs: Vec<&String> = files.iter().filter(|f| f.ends_with(".svg")).collect();
    assert!(pngs.len() >= 4, "{files:?}");
    assert_eq!(pngs.len(), svgs.len(), "{files:?}");
    for kind in ["topdown_", "figure1_", "figure3_"] {
        assert!(
            files.iter().any(|f| f.starts_with(kind)),
            "no {kind} in {files:?}"
        );
    }
    assert!(
        files.iter().all(|f| !f.starts_with('.')),
        "temporary files left: {files:?}"
    );
    for file in pngs {
        check_png(&out.join(file));
    }
    for file in svgs {
        check_svg(&out.join(file));
    }
    // Same seed, same summary (the timing line aside).
    let again = succeed(&[
        "demo",
        "--seconds",
        "3",
        "--seed",
        "7",
        "--no-plots",
        "--out",
        out.to_str().unwrap(),
    ]);
    let without_cost = |s: &str| {
        s.lines()
            .filter(|l| !l.contains("cost:") && !l.contains(".png") && !l.contains(".svg"))
            .filter(|l| !l.contains("pictures:"))
            .collect::<Vec<_>>()
            .join("\n")
    };
    assert_eq!(without_cost(&stdout), without_cost(&again));
}

/// `frame,id,x,y` rows of a trajectory file.
fn read_rows(path: &Path) -> Vec<(f64, u64)> {
    std::fs::read_to_string(path)
        .unwrap()
        .lines()
        .skip(1)
        .map(|line| {
            let fields: Vec<&str> = line.split(',').collect();
            (fields[0].parse().unwrap(), fields[1].parse().unwrap())
        })
        .collect()
}

/// Runs `annotate` on a window of a real file and checks every person-frame is there, with
/// no NaN; returns the attentive fraction.
fn annotate_window(
    file: &str,
    seconds_per_frame: f64,
    start: f64,
    end: f64,
    fps: f64,
    offline: bool,
) -> f64 {
    let input = data(&format!("pedestrians/{file}"));
    let directory = tempfile::tempdir().unwrap();
    let out = directory.path().join("gaze.csv");
    let mut args = vec![
        "annotate".to_string(),
        "--input".into(),
        input.to_str().unwrap().into(),
        "--out".into(),
        out.to_str().unwrap().into(),
        "--fps".into(),
        fps.to_string(),
        "--start".into(),
        start.to_string(),
        "--end".into(),
        end.to_string(),
    ];
    if offline {
        args.push("--offline".into());
    }
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    let stdout = succeed(&args);
    println!("{stdout}");

    // Expected person-frames: the output grid (anchored at the file's first sample) within
    // the window and within each person's track.
    let rows = read_rows(&input);
    let mut spans: HashMap<u64, (f64, f64)> = HashMap::new();
    for &(frame, id) in &rows {
        let t = frame * seconds_per_frame;
        let span = spans.entry(id).or_insert((t, t));
        span.0 = span.0.min(t);
        span.1 = span.1.max(t);
    }
    let anchor = spans.values().map(|s| s.0).fold(f64::INFINITY, f64::min);
    let last = spans
        .values()
        .map(|s| s.1)
        .fold(f64::NEG_INFINITY, f64::max);
    let mut expected = BTreeSet::new();
    let mut k = 0u64;
    loop {
        let t = anchor + k as f64 / fps;
        k += 1;
        if t > end.min(last) + 1e-6 {
            break;
        }
        if t < start - 1e-6 {
            continue;
        }
        for (&id, &(first, last)) in &spans {
            if first - 1e-6 <= t && t <= last + 1e-6 {
                expected.insert(((t * 1e3).round() as i64, id));
            }
        }
    }

    let csv = std::fs::read_to_string(&out).unwrap();
    let mut lines = csv.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    assert_eq!(
        &header[..10],
        &[
            "time",
            "id",
            "target",
            "part",
            "attending",
            "s_max",
            "threshold",
            "gaze_x",
            "gaze_y",
            "gaze_z"
        ]
    );
    assert_eq!(
        header.len(),
        10 + 4 * 10 + 2 + 2,
        "10 chain joints of 4 components, then the lids, talking and group"
    );
    assert_eq!(
        &header[50..],
        &["left_closure", "right_closure", "talking", "group"]
    );
    let mut got = BTreeSet::new();
    let (mut attending, mut count, mut blinking) = (0usize, 0usize, 0usize);
    for line in lines {
        let fields: Vec<&str> = line.split(',').collect();
        assert_eq!(fields.len(), header.len(), "{line}");
        let t: f64 = fields[0].parse().unwrap();
        let id: u64 = fields[1].parse().unwrap();
        assert!(
            got.insert(((t * 1e3).round() as i64, id)),
            "duplicate row {line}"
        );
        // No talking and no groups in a file without those columns.
        assert_eq!(&fields[52..], &["0", ""], "{line}");
        for (name, value) in header.iter().zip(&fields).skip(5).take(47) {
            let value: f64 = value
                .parse()
                .unwrap_or_else(|_| panic!("{name} = {value} in {line}"));
            assert!(value.is_finite(), "{name} = {value} in {line}");
        }
        let flag = fields[4] == "1";
        assert_eq!(flag, !fields[2].is_empty(), "{line}");
        attending += usize::from(flag);
        count += 1;
        // Unit quaternions and gaze direction.
        for joint in 0..10 {
            let q: Vec<f64> = (0..4)
                .map(|c| fields[10 + 4 * joint + c].parse().unwrap())
                .collect();
            let norm = q.iter().map(|v| v * v).sum::<f64>().sqrt();
            assert!((norm - 1.0).abs() < 1e-3, "{line}");
        }
        // Lid closures: 0 open to 1 closed, both eyes together.
        let closures: Vec<f64> = fields[50..52].iter().map(|v| v.parse().unwrap()).collect();
        for closure in &closures {
            assert!((0.0..=1.0).contains(closure), "closure {closure} in {line}");
        }
        assert_eq!(closures[0], closures[1], "both eyes blink together: {line}");
        blinking += usize::from(closures[0] > 0.0);
    }
    assert_eq!(got.len(), expected.len(), "person-frames");
    assert_eq!(got, expected, "every person-frame in range, and only those");
    let fraction = attending as f64 / count as f64;
    println!(
        "{file} [{start} s, {end} s] at {fps} fps{}: {count} person-frames, attentive {:.1}%, \
         lids closing or closed in {blinking}",
        if offline { " offline" } else { "" },
        100.0 * fraction
    );
    // Minutes of people at about 17 blinks a minute: some samples fall in a blink.
    assert!(blinking > 0, "no sample has its lids closing in {count}");
    fraction
}

#[test]
fn annotate_eth_seq_eth_covers_every_person_frame() {
    // seq_eth: 6 frame numbers per 0.4 s sample, 1/15 s each.
    let fraction = annotate_window("eth_seq_eth.csv", 1.0 / 15.0, 100.0, 400.0, 10.0, false);
    // Attention percentages are drawn in [20%, 60%); online, people attend about that.
    assert!((0.15..0.6).contains(&fraction), "attentive {fraction}");
}

#[test]
fn annotate_ucy_zara01_covers_every_person_frame_online_and_offline() {
    // zara01: 10 frame numbers per 0.4 s sample, 1/25 s each.
    let fraction = annotate_window("ucy_zara01.csv", 1.0 / 25.0, 0.0, 200.0, 10.0, false);
    assert!((0.15..0.6).contains(&fraction), "attentive {fraction}");
    let fraction = annotate_window("ucy_zara01.csv", 1.0 / 25.0, 50.0, 150.0, 2.5, true);
    assert!(
        (0.15..0.6).contains(&fraction),
        "attentive offline {fraction}"
    );
}

#[test]
fn annotate_runs_every_attention_model() {
    let input = data("pedestrians/ucy_zara01.csv");
    let directory = tempfile::tempdir().unwrap();
    let out = directory.path().join("gaze.csv");
    for model in ["crowd", "saliency", "baseline"] {
        succeed(&[
            "annotate",
            "--input",
            input.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
            "--model",
            model,
            "--start",
            "0",
            "--end",
            "30",
            "--fps",
            "10",
        ]);
        let text = std::fs::read_to_string(&out).unwrap();
        let header: Vec<&str> = text.lines().next().unwrap().split(',').collect();
        let part = header.iter().position(|name| *name == "part").unwrap();
        let target = header.iter().position(|name| *name == "target").unwrap();
        let rows: Vec<Vec<&str>> = text
            .lines()
            .skip(1)
            .map(|l| l.split(',').collect())
            .collect();
        assert!(rows.len() > 100, "{model}: {} rows", rows.len());
        let on_parts = rows
            .iter()
            .filter(|row| !row[target].is_empty() && row[part] != "whole")
            .count();
        let looking = rows.iter().filter(|row| !row[target].is_empty()).count();
        println!(
            "{model}: {} rows, {looking} looking at someone, {on_parts} at a body part",
            rows.len()
        );
        assert!(looking > 0, "{model} never looked at anyone");
        match model {
            // The saliency model looks at body parts; the others at whole entities (the
            // baseline at heads).
            "saliency" => assert!(on_parts > 0),
            "crowd" => assert_eq!(on_parts, 0),
            _ => {}
        }
    }
}

#[test]
fn bvh_reads_writes_and_reads_the_same_skeleton_and_motion() {
    for name in ["zombie.bvh", "wave_hello.bvh"] {
        let path = data(&format!("bvh/{name}"));
        let bvh = Bvh::read(&path).unwrap();
        assert_eq!(bvh.joints.len(), 27);
        assert_eq!(bvh.channel_count, 84);
        // The thumbs rotate in another order than the rest.
        let thumb = &bvh.joints[bvh.joint("RightHandThumb1").unwrap()];
        assert_eq!(thumb.euler_order(), Some(glam::EulerRot::YXZ));
        let again = Bvh::parse(&bvh.to_text(), Path::new(name)).unwrap();
        assert_eq!(bvh.joints.len(), again.joints.len());
        for (a, b) in bvh.joints.iter().zip(&again.joints) {
            assert_eq!(
                (&a.name, a.parent, &a.channels),
                (&b.name, b.parent, &b.channels)
            );
            assert!(a.offset.abs_diff_eq(b.offset, 1e-4));
            assert_eq!(a.end_site.is_some(), b.end_site.is_some());
            if let (Some(x), Some(y)) = (a.end_site, b.end_site) {
                assert!(x.abs_diff_eq(y, 1e-4));
            }
        }
        assert!((bvh.frame_time - again.frame_time).abs() < 1e-7);
        assert_eq!(bvh.frames.len(), again.frames.len());
        for (a, b) in bvh.frames.iter().zip(&again.frames) {
            for (x, y) in a.iter().zip(b) {
                assert!((x - y).abs() <= 1e-4, "{x} {y}");
            }
        }
    }
}

/// A small scene: person 1 walks 10 m along x; person 2 comes the other way 1.5 m to the
/// side; person 3 stands ahead to the left; person 4 overtakes person 1.
fn small_scene(path: &Path) {
    let mut csv = String::from("frame,id,x,y\n");
    for k in 0..=20 {
        let t = k as f64 * 0.4;
        let frame = k * 10;
        csv += &format!("{frame},1,{},0\n", 1.2 * t);
        csv += &format!("{frame},2,{},1.5\n", 10.0 - 1.3 * t);
        csv += &format!("{frame},3,6,3\n");
        csv += &format!("{frame},4,{},-1\n", -3.0 + 1.8 * t);
    }
    std::fs::write(path, csv).unwrap();
}

/// `crowdgaze bvh` with `clip` walking person 1's path of `trajectory` into `out`; its
/// output.
fn bvh_walk(clip: &Path, trajectory: &Path, out: &Path) -> String {
    succeed(&[
        "bvh",
        "--skeleton",
        clip.to_str().unwrap(),
        "--trajectory",
        trajectory.to_str().unwrap(),
        "--id",
        "1",
        "--out",
        out.to_str().unwrap(),
        "--seed",
        "3",
    ])
}

#[test]
fn bvh_adds_gaze_to_a_real_clip_walking_a_trajectory() {
    let clip_path = data("bvh/zombie.bvh");
    let directory = tempfile::tempdir().unwrap();
    let trajectory = directory.path().join("walk.csv");
    small_scene(&trajectory);
    let out = directory.path().join("out.bvh");
    let stdout = bvh_walk(&clip_path, &trajectory, &out);
    println!("{stdout}");
    assert!(
        stdout.contains("Hips > Spine > Spine1 > Spine2 > Spine3 > Neck > Head"),
        "{stdout}"
    );
    let clip = Bvh::read(&clip_path).unwrap();
    let result = Bvh::read(&out).unwrap();
    // Same hierarchy and channel orders.
    assert_eq!(result.joints, clip.joints);
    assert_eq!(result.frame_time, clip.frame_time);
    // 8 s at 30 fps.
    assert_eq!(result.frames.len(), 241);
    let head = clip.joint("Head").unwrap();
    let hips = clip.joint("Hips").unwrap();
    let mut turned = 0;
    let mut largest: f64 = 0.0;
    let mut largest_turn: f64 = 0.0;
    for (k, frame) in result.frames.iter().enumerate() {
        let original = &clip.frames[k % clip.frames.len()];
        let a = clip.joints[head].rotation(original);
        let b = clip.joints[head].rotation(frame);
        let angle = a.angle_between(b).to_degrees();
        largest = largest.max(angle);
        if angle > 1.0 {
            turned += 1;
        }
        // The root follows the trajectory: x of the file along the rest facing (-Y), in
        // inches, at the clip's own height.
        let t = k as f64 / 30.0;
        let root = clip.joints[hips].translation(frame).unwrap();
        let expected = DVec3::new(0.0, -1.2 * t * 39.37, 0.0);
        assert!(
            (root.x - expected.x).abs() < 1.0 && (root.y - expected.y).abs() < 1.0,
            "frame {k}: root {root} expected {expected}"
        );
        assert!((root.z - clip.joints[hips].translation(original).unwrap().z).abs() < 1e-4);
        // And faces the way it walks (-Y).
        let facing = global_rotation(&result, hips, frame) * DVec3::NEG_Y;
        let yaw = facing.x.atan2(-facing.y).to_degrees();
        assert!(yaw.abs() < 25.0, "frame {k}: hips yaw {yaw}");
        // The head turns at most about 110° from the hips (spine 40°, neck and head 70°),
        // never backwards.
        let head_facing = global_rotation(&result, head, frame) * DVec3::NEG_Y;
        let turn = head_facing.dot(facing).clamp(-1.0, 1.0).acos().to_degrees();
        largest_turn = largest_turn.max(turn);
        assert!(turn < 125.0, "frame {k}: head {turn} degrees from the hips");
    }
    println!(
        "head joint turned on {turned} of {} frames, up to {largest:.1} degrees; head up to \
         {largest_turn:.1} degrees from the hips",
        result.frames.len()
    );
    // Person 3 stands 3 m to the left of the path: at some point the head looks well aside.
    assert!(largest_turn > 45.0, "{largest_turn}");
    assert!(turned > 10, "the head turns on some frames");
    assert!(
        largest > 5.0 && largest < 90.0,
        "largest head turn {largest}"
    );
    // Joints away from the chain are the clip's.
    let arm = &clip.joints[clip.joint("LeftForeArm").unwrap()];
    for (k, frame) in result.frames.iter().enumerate() {
        let original = &clip.frames[k % clip.frames.len()];
        let range = arm.first_channel..arm.first_channel + arm.channels.len();
        assert_eq!(&frame[range.clone()], &original[range]);
    }
}

/// zombie.bvh with eyes under a facial joint (as Character Creator's and MetaHuman's hang
/// from a facial root): `FacialRoot` under `Head`, turned 6° in every frame, and `LeftEye`,
/// `RightEye` under it.
fn clip_with_facial_eyes(path: &Path) {
    let text = std::fs::read_to_string(data("bvh/zombie.bvh")).unwrap();
    let head_end = "\t\t\t\t\t\t\tEnd Site\n\t\t\t\t\t\t\t{\n\t\t\t\t\t\t\t\tOFFSET 0.00000 0.00000 3.73175\n\t\t\t\t\t\t\t}\n";
    assert!(text.contains(head_end), "zombie.bvh's head changed");
    let eye = |name: &str, x: f64| {
        format!(
            "JOINT {name}\n{{\nOFFSET {x} -3.0 2.5\nCHANNELS 3 Xrotation Yrotation Zrotation\n\
             End Site\n{{\nOFFSET 0 -0.5 0\n}}\n}}\n"
        )
    };
    let facial = format!(
        "JOINT FacialRoot\n{{\nOFFSET 0 0 0.5\nCHANNELS 3 Xrotation Yrotation Zrotation\n{}{}}}\n",
        eye("LeftEye", 1.2),
        eye("RightEye", -1.2)
    );
    let (hierarchy, motion) = text.split_once("MOTION").unwrap();
    let mut out = hierarchy.replacen(head_end, &facial, 1) + "MOTION";
    for line in motion.lines().skip(1) {
        let values: Vec<&str> = line.split_whitespace().collect();
        if values.len() > 24 && !line.starts_with("Frame") {
            // Hips (6 channels) and Spine..Head (6 x 3) come first; the new joints follow.
            out += &format!(
                "\n{} 6.0 0.0 0.0 0.0 0.0 0.0 0.0 0.0 0.0 {}",
                values[..24].join(" "),
                values[24..].join(" ")
            );
        } else {
            out += "\n";
            out += line;
        }
    }
    out += "\n";
    std::fs::write(path, out).unwrap();
}

#[test]
fn bvh_turns_eyes_under_a_facial_joint() {
    let directory = tempfile::tempdir().unwrap();
    let clip_path = directory.path().join("facial.bvh");
    clip_with_facial_eyes(&clip_path);
    let trajectory = directory.path().join("walk.csv");
    small_scene(&trajectory);
    let out = directory.path().join("out.bvh");
    let stdout = bvh_walk(&clip_path, &trajectory, &out);
    assert!(
        stdout.contains("Neck > Head > LeftEye > RightEye"),
        "{stdout}"
    );
    let clip = Bvh::read(&clip_path).unwrap();
    let result = Bvh::read(&out).unwrap();
    assert_eq!(result.joints, clip.joints);
    let facial = &clip.joints[clip.joint("FacialRoot").unwrap()];
    let eye = &clip.joints[clip.joint("LeftEye").unwrap()];
    let mut eye_turned = 0;
    for (k, frame) in result.frames.iter().enumerate() {
        let original = &clip.frames[k % clip.frames.len()];
        // The facial joint is read, never written.
        let range = facial.first_channel..facial.first_channel + 3;
        assert_eq!(&frame[range.clone()], &original[range]);
        let angle = eye
            .rotation(original)
            .angle_between(eye.rotation(frame))
            .to_degrees();
        if angle > 1.0 {
            eye_turned += 1;
        }
    }
    assert!(eye_turned > 10, "the eyes turned on {eye_turned} frames");
}

#[test]
fn plot_draws_a_trajectory_file_and_figure_3() {
    let input = data("pedestrians/ucy_zara01.csv");
    let directory = tempfile::tempdir().unwrap();
    let out = directory.path().join("plots");
    let stdout = succeed(&[
        "plot",
        "--input",
        input.to_str().unwrap(),
        "--start",
        "20",
        "--end",
        "60",
        "--fps",
        "5",
        "--times",
        "30,50",
        "--out",
        out.to_str().unwrap(),
    ]);
    println!("{stdout}");
    let files = entries(&out);
    assert!(
        files.contains("topdown_30.0s.png") && files.contains("topdown_50.0s.svg"),
        "{files:?}"
    );
    assert!(
        files.iter().any(|f| f.starts_with("figure1_person")),
        "{files:?}"
    );
    assert!(files.contains("figure3_gaze_shift.png"), "{files:?}");
    assert!(
        files.iter().any(|f| f.starts_with("eyes_person")),
        "{files:?}"
    );
    for file in &files {
        let path = out.join(file);
        if file.ends_with(".png") {
            check_png(&path);
        } else {
            check_svg(&path);
        }
    }
}

#[test]
fn plot_draws_the_eyes_and_lids_of_one_character() {
    let directory = tempfile::tempdir().unwrap();
    let out = directory.path().join("plots");
    let stdout = succeed(&[
        "plot",
        "--what",
        "eyes",
        "--seconds",
        "30",
        "--characters",
        "40",
        "--objects",
        "20",
        "--character",
        "2",
        "--out",
        out.to_str().unwrap(),
        "-q",
    ]);
    println!("{stdout}");
    // Only the eyes picture, as PNG and SVG.
    let files = entries(&out);
    assert_eq!(
        files,
        BTreeSet::from([
            "eyes_character2.png".to_string(),
            "eyes_character2.svg".to_string()
        ])
    );
    for file in &files {
        assert!(
            std::fs::metadata(out.join(file)).unwrap().len() > 0,
            "{file}"
        );
    }
    check_png(&out.join("eyes_character2.png"));
    let svg = out.join("eyes_character2.svg");
    check_svg(&svg);
    // 20 s of a walking character: its gaze shifts, labelled by amplitude, and its blinks.
    let svg = std::fs::read_to_string(&svg).unwrap();
    let document = roxmltree::Document::parse(&svg).unwrap();
    let texts: Vec<String> = document
        .descendants()
        .filter(|n| n.tag_name().name() == "text")
        .filter_map(|n| n.text().map(|t| t.trim().to_string()))
        .collect();
    let amplitudes: Vec<f64> = texts
        .iter()
        .filter_map(|t| t.strip_suffix('°')?.parse().ok())
        .collect();
    let title = texts
        .iter()
        .find(|t| t.starts_with("The eyes of character 2"))
        .expect("the title");
    let count = |what: &str| -> usize {
        let before = title.split(&format!(" {what}")).next().unwrap();
        let digits = before.rsplit(|c: char| !c.is_ascii_digit()).next().unwrap();
        digits.parse().unwrap()
    };
    let (shifts, blinks) = (count("shifts"), count("blinks seen"));
    println!("{shifts} gaze shifts (amplitudes {amplitudes:?} degrees), {blinks} blinks");
    assert_eq!(amplitudes.len(), shifts, "one label per gaze shift");
    assert!(amplitudes.iter().all(|a| (0.0..=180.0).contains(a)));
    assert!(shifts > 0 && blinks > 0, "{title}");
}

/// Two people walk up to each other and stand talking in turns of 4 s (group 7): person 1
/// talks from 2 s to 6 s, person 2 from 6 s to 10 s, and so on to 20 s. Person 3 walks by,
/// in no group; person 4 stands alone in group 9 (a group of one: no conversation). The
/// columns come in another order than usual.
fn conversation_scene(path: &Path) {
    let mut csv = String::from("frame,id,group,x,y,talking\n");
    for k in 0..=50 {
        let frame = 10 * k;
        let t = k as f64 * 0.4;
        let walked = (1.2 * t).min(2.4);
        let (first, second) = (talker(k, 1), talker(k, 2));
        csv += &format!("{frame},1,7,{},0,{}\n", -2.4 + walked, u8::from(first));
        csv += &format!("{frame},2,7,{},0,{}\n", 3.6 - walked, u8::from(second));
        csv += &format!("{frame},3,,{},3,0\n", -5.0 + 0.65 * t);
        csv += &format!("{frame},4,9,5,-3,\n");
    }
    std::fs::write(path, csv).unwrap();
}

/// Whether person 1 or 2 of [`conversation_scene`] talks from sample `k` (0.4 s each).
fn talker(k: usize, person: u64) -> bool {
    k >= 5 && ((k - 5) / 10) % 2 == (person - 1) as usize
}

#[test]
fn annotate_reads_talking_and_groups_and_listeners_look_at_the_speaker() {
    let directory = tempfile::tempdir().unwrap();
    let input = directory.path().join("talk.csv");
    conversation_scene(&input);
    let out = directory.path().join("gaze.csv");
    for offline in [false, true] {
        let mut args = vec![
            "annotate",
            "--input",
            input.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
            "--fps",
            "10",
            "-q",
        ];
        if offline {
            args.push("--offline");
        }
        let stdout = succeed(&args);
        println!("{stdout}");
        assert!(stdout.contains("2 people talk"), "{stdout}");
        assert!(
            stdout.contains("groups:      1 standing together and talking in turns (2 people)"),
            "{stdout}"
        );
        let csv = std::fs::read_to_string(&out).unwrap();
        let mut lines = csv.lines();
        let header: Vec<&str> = lines.next().unwrap().split(',').collect();
        let column = |name: &str| header.iter().position(|h| *h == name).unwrap();
        let (talking, group, target) = (column("talking"), column("group"), column("target"));
        assert_eq!((talking, group), (52, 53), "after the lid closures");
        // Per person: (time, talking, group, target).
        let mut rows: HashMap<u64, Vec<(f64, bool, String, String)>> = HashMap::new();
        for line in lines {
            let fields: Vec<&str> = line.split(',').collect();
            assert_eq!(fields.len(), header.len(), "{line}");
            assert!(["0", "1"].contains(&fields[talking]), "{line}");
            rows.entry(fields[1].parse().unwrap()).or_default().push((
                fields[0].parse().unwrap(),
                fields[talking] == "1",
                fields[group].to_string(),
                fields[target].to_string(),
            ));
        }
        assert_eq!(rows.len(), 4);
        for (person, rows) in &rows {
            assert_eq!(rows.len(), 201, "20 s at 10 fps");
            for (t, talks, group, _) in rows {
                // Talking holds from each sample (0.4 s) to the next.
                let k = (t / 0.4 + 1e-6).floor() as usize;
                let expected = matches!(person, 1 | 2) && talker(k, *person);
                assert_eq!(*talks, expected, "person {person} at {t} s");
                // Only the two form a conversation: person 4's group has one person.
                let expected = if matches!(person, 1 | 2) { "7" } else { "" };
                assert_eq!(group, expected, "person {person} at {t} s");
            }
        }
        // While one talks the other mostly looks at them (Argyle & Ingham: 75% of the time).
        let mut on_speaker = [0usize; 2];
        let mut listening = [0usize; 2];
        for (listener, speaker) in [(1u64, 2u64), (2, 1)] {
            let slot = (listener - 1) as usize;
            for ((_, listener_talks, _, target), (_, speaker_talks, _, _)) in
                rows[&listener].iter().zip(&rows[&speaker])
            {
                if *speaker_talks && !listener_talks {
                    listening[slot] += 1;
                    on_speaker[slot] += usize::from(*target == speaker.to_string());
                }
            }
        }
        let share = |slot: usize| on_speaker[slot] as f64 / listening[slot] as f64;
        println!(
            "{}: person 1 looks at person 2 in {:.0}% of 2's talking frames, 2 at 1 in {:.0}% \
             of 1's",
            if offline { "offline" } else { "online" },
            100.0 * share(0),
            100.0 * share(1)
        );
        assert!(listening.iter().all(|&n| n >= 60), "{listening:?}");
        assert!(
            share(0) > 0.5 && share(1) > 0.5,
            "{on_speaker:?} of {listening:?}"
        );
    }
}

/// Runs `args` (with `{dir}` replaced by a fresh directory holding `name` = `content`) and
/// checks the failure: non-zero exit, one line naming `name:line`, nothing written.
fn check_bad_input(name: &str, content: &str, args: &[&str], line: &str) {
    let directory = tempfile::tempdir().unwrap();
    let input = directory.path().join(name);
    std::fs::write(&input, content).unwrap();
    let before = entries(directory.path());
    let args: Vec<String> = args
        .iter()
        .map(|a| a.replace("{dir}", directory.path().to_str().unwrap()))
        .collect();
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    let output = crowdgaze(&args);
    let stderr = text(&output.stderr);
    assert_eq!(output.status.code(), Some(1), "{args:?}: {stderr}");
    assert_eq!(stderr.trim_end().lines().count(), 1, "one line: {stderr}");
    let wanted = format!("{name}:{line}");
    assert!(
        stderr.contains(&wanted),
        "{args:?}: '{wanted}' not in {stderr}"
    );
    assert_eq!(
        entries(directory.path()),
        before,
        "no output file, no temporary file"
    );
    println!("{}", stderr.trim_end());
}

#[test]
fn bad_trajectory_files_fail_with_file_and_line_and_leave_nothing() {
    let annotate = [
        "annotate",
        "--input",
        "{dir}/bad.csv",
        "--out",
        "{dir}/gaze.csv",
    ];
    let good = "frame,id,x,y\n0,1,0,0\n10,1,0.5,0\n20,1,1,0\n0,2,3,3\n10,2,3,2.5\n";
    check_bad_input("bad.csv", "frame,id,x\n0,1,0\n", &annotate, "1");
    check_bad_input(
        "bad.csv",
        &good.replace("10,1,0.5,0", "10,1,abc,0"),
        &annotate,
        "3",
    );
    check_bad_input(
        "bad.csv",
        &good.replace("10,1,0.5,0", "10,one,0.5,0"),
        &annotate,
        "3",
    );
    check_bad_input(
        "bad.csv",
        &good.replace("20,1,1,0", "20,1,NaN,0"),
        &annotate,
        "4",
    );
    check_bad_input(
        "bad.csv",
        &good.replace("20,1,1,0", "5,1,1,0"),
        &annotate,
        "4",
    );
    check_bad_input(
        "bad.csv",
        &good.replace("20,1,1,0", "20,1,1"),
        &annotate,
        "4",
    );
    check_bad_input("bad.csv", "frame,id,x,y\n", &annotate, "1");
    // The talking and group columns.
    let talk =
        "frame,id,x,y,talking,group\n0,1,0,0,0,3\n10,1,0.5,0,1,3\n0,2,1,1,,3\n10,2,1,1,0,3\n";
    check_bad_input(
        "bad.csv",
        &talk.replace("0.5,0,1,3", "0.5,0,2,3"),
        &annotate,
        "3",
    );
    check_bad_input(
        "bad.csv",
        &talk.replace("0,2,1,1,,3", "0,2,1,1,,x"),
        &annotate,
        "4",
    );
    // A person's group does not change.
    check_bad_input(
        "bad.csv",
        &talk.replace("10,2,1,1,0,3", "10,2,1,1,0,4"),
        &annotate,
        "5",
    );
    // At most 8 people in a group: the 9th's first row.
    let mut crowded = String::from("frame,id,x,y,group\n");
    for person in 0..9 {
        crowded += &format!("0,{person},{person},0,5\n10,{person},{person},1,5\n");
    }
    check_bad_input("bad.csv", &crowded, &annotate, "18");
    // Plot and bvh read trajectories the same way.
    check_bad_input(
        "bad.csv",
        &good.replace("10,2,3,2.5", "10,2,3,inf"),
        &["plot", "--input", "{dir}/bad.csv", "--out", "{dir}/plots"],
        "6",
    );
}

#[test]
fn bvh_command_rejects_bad_input() {
    let clip = data("bvh/zombie.bvh");
    let clip = clip.to_str().unwrap().to_string();
    let good = "frame,id,x,y\n0,1,0,0\n10,1,0.5,0\n20,1,1,0\n0,2,3,3\n10,2,3,2.5\n";
    let bvh = |id: &str| -> Vec<String> {
        [
            "bvh",
            "--skeleton",
            &clip,
            "--trajectory",
            "{dir}/walk.csv",
            "--id",
            id,
            "--out",
            "{dir}/out.bvh",
        ]
        .iter()
        .map(|s| s.to_string())
        .collect()
    };
    let args = bvh("99");
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    // An unknown id names the file and its data lines.
    check_bad_input("walk.csv", good, &args, "2-6");
    let args = bvh("1");
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    check_bad_input("walk.csv", &good.replace("0,2,3,3", "0,2,x,3"), &args, "5");
    // A broken BVH names its line.
    let source = std::fs::read_to_string(&clip).unwrap();
    let broken = source.replacen(
        "OFFSET 0.00000 1.15266 1.72900",
        "OFFSET 0.00000 oops 1.72900",
        1,
    );
    let line = source
        .lines()
        .position(|l| l.contains("OFFSET 0.00000 1.15266 1.72900"))
        .unwrap()
        + 1;
    let directory = tempfile::tempdir().unwrap();
    std::fs::write(directory.path().join("walk.csv"), good).unwrap();
    let skeleton = directory.path().join("broken.bvh");
    std::fs::write(&skeleton, broken).unwrap();
    let out = directory.path().join("out.bvh");
    let output = crowdgaze(&[
        "bvh",
        "--skeleton",
        skeleton.to_str().unwrap(),
        "--trajectory",
        directory.path().join("walk.csv").to_str().unwrap(),
        "--id",
        "1",
        "--out",
        out.to_str().unwrap(),
    ]);
    let stderr = text(&output.stderr);
    assert_eq!(output.status.code(), Some(1), "{stderr}");
    assert!(stderr.contains(&format!("broken.bvh:{line}:")), "{stderr}");
    assert!(!out.exists());
}

/// The numbers of a summary line `  <key>  ...`, in order.
fn numbers_of(stdout: &str, key: &str) -> Vec<f64> {
    let line = stdout
        .lines()
        .find_map(|l| l.trim().strip_prefix(key))
        .unwrap_or_else(|| panic!("no '{key}' line in {stdout}"));
    line.split(|c: char| !(c.is_ascii_digit() || c == '.'))
        .filter_map(|w| w.trim_matches('.').parse().ok())
        .collect()
}

/// The summary without the lines that vary from run to run (timing) or name files.
fn stable_summary(stdout: &str) -> String {
    stdout
        .lines()
        .filter(|l| !l.contains("cost:") && !l.contains("pictures:"))
        .filter(|l| !l.contains(".png") && !l.contains(".svg"))
        .collect::<Vec<_>>()
        .join("\n")
}

#[test]
fn demo_look_up_shows_passers_by_following_a_group_looking_up() {
    let directory = tempfile::tempdir().unwrap();
    let out = directory.path().join("look-up");
    let run = |extra: &[&str]| {
        let mut args = vec![
            "demo",
            "--scene",
            "look-up",
            "--seconds",
            "20",
            "--look-at",
            "5",
            "-q",
            "--out",
            out.to_str().unwrap(),
        ];
        args.extend_from_slice(extra);
        succeed(&args)
    };
    // The default seed and five lookers.
    let stdout = run(&[]);
    println!("{stdout}");
    let lookers = numbers_of(&stdout, "lookers:");
    assert_eq!(lookers[0], 5.0, "{stdout}");
    assert_eq!(lookers[1], 5.0, "they stop at 5 s: {stdout}");
    assert_eq!(lookers[2], 10.0, "10 m up: {stdout}");
    let saw = numbers_of(&stdout, "saw them:")[0];
    let looked = numbers_of(&stdout, "looked up:");
    let (followers, of_seen, seen, unseen) = (looked[0], looked[1], looked[2], looked[4]);
    assert!(followers >= 1.0, "nobody followed: {stdout}");
    assert_eq!(seen, saw, "{stdout}");
    assert!(of_seen <= saw, "{stdout}");
    assert_eq!(of_seen + unseen, followers, "{stdout}");
    let at_once = numbers_of(&stdout, "at once:")[0];
    assert!(at_once >= 1.0 && at_once <= followers, "{stdout}");
    // The picture: a top-down view with the followers and a timeline.
    let files = entries(&out);
    assert!(
        files.contains("look_up.png") && files.contains("look_up.svg"),
        "{files:?}"
    );
    check_png(&out.join("look_up.png"));
    check_svg(&out.join("look_up.svg"));
    let svg = std::fs::read_to_string(out.join("look_up.svg")).unwrap();
    assert!(svg.contains("looked up too"), "no followers' legend");
    assert!(svg.contains("people looking up because others do"));
    // Deterministic: the same summary again.
    let again = run(&["--no-plots"]);
    assert_eq!(stable_summary(&stdout), stable_summary(&again));
    // Following off: the same people stop and the same passers-by see them; nobody looks up.
    let off = run(&["--no-follow", "--no-plots"]);
    println!("{off}");
    assert!(off.contains("following off"), "{off}");
    let line = |s: &str, key: &str| {
        s.lines()
            .find(|l| l.trim().starts_with(key))
            .map(str::to_string)
    };
    assert_eq!(line(&off, "lookers:"), line(&stdout, "lookers:"));
    assert_eq!(line(&off, "saw them:"), line(&stdout, "saw them:"));
    let looked_off = numbers_of(&off, "looked up:");
    assert_eq!(looked_off[0], 0.0, "{off}");
    assert!(off.contains("0 glances in all"), "{off}");
    assert!(!off.contains("at once:"), "{off}");
    // The weaker strength draws fewer.
    let gallup = run(&["--follow-strength", "gallup", "--no-plots"]);
    assert!(gallup.contains("following on (gallup)"), "{gallup}");
    assert!(numbers_of(&gallup, "looked up:")[0] < followers, "{gallup}");
    // The plain demo is still the default scene.
    let plain = succeed(&["demo", "--seconds", "1", "--no-plots", "-q"]);
    assert!(plain.contains("attentive:") && !plain.contains("lookers:"));
    // Bad settings are refused by name.
    for (args, flag) in [
        (vec!["--lookers", "0"], "--lookers"),
        (vec!["--look-at", "30"], "--look-at"),
    ] {
        let mut all = vec![
            "demo",
            "--scene",
            "look-up",
            "--seconds",
            "20",
            "--no-plots",
        ];
        all.extend_from_slice(&args);
        let output = crowdgaze(&all);
        let stderr = text(&output.stderr);
        assert!(!output.status.success(), "{all:?}");
        assert!(stderr.contains(flag), "{all:?}: {stderr}");
    }
}

/// `annotate --input INPUT --out OUT`.
fn annotate_args<'a>(input: &'a Path, out: &'a Path) -> Vec<&'a str> {
    vec![
        "annotate",
        "--input",
        input.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]
}

/// Annotates zara01's first 40 s at 10 fps with `extra` arguments; returns the header's
/// names and the rows.
fn annotate_zara(out: &Path, extra: &[&str]) -> (Vec<String>, Vec<Vec<String>>, String) {
    let input = data("pedestrians/ucy_zara01.csv");
    let mut args = annotate_args(&input, out);
    args.extend_from_slice(&["--start", "0", "--end", "40", "--fps", "10", "-q"]);
    args.extend_from_slice(extra);
    let stdout = succeed(&args);
    let text = std::fs::read_to_string(out).unwrap();
    let mut lines = text.lines();
    let header = lines
        .next()
        .unwrap()
        .split(',')
        .map(str::to_string)
        .collect();
    let rows = lines
        .map(|l| l.split(',').map(str::to_string).collect())
        .collect();
    (header, rows, stdout)
}

#[test]
fn annotate_follows_people_made_to_stare_and_writes_the_followed_point() {
    let directory = tempfile::tempdir().unwrap();
    let out = directory.path().join("gaze.csv");
    let (plain_header, plain_rows, _) = annotate_zara(&out, &[]);
    assert_eq!(plain_header.last().map(String::as_str), Some("group"));
    // Following on, nobody staring: the three columns are there and empty.
    let (header, rows, stdout) = annotate_zara(&out, &["--follow"]);
    assert_eq!(header[..plain_header.len()], plain_header[..]);
    assert_eq!(
        header[plain_header.len()..],
        ["follow_x", "follow_y", "follow_z"]
    );
    assert_eq!(rows.len(), plain_rows.len());
    assert!(rows.iter().all(|row| row.len() == header.len()));
    assert!(rows
        .iter()
        .all(|row| row[plain_header.len()..].iter().all(String::is_empty)));
    assert!(stdout.contains("following:   0 people"), "{stdout}");
    // Two people stare at a point 8 m up: others near them glance at it.
    let stares = [
        "--follow",
        "--model",
        "street",
        "--stare",
        "1:5,5,8",
        "--stare",
        "2:5,5,8:0-5",
    ];
    let (header, rows, stdout) = annotate_zara(&out, &stares);
    println!("{stdout}");
    assert!(stdout.contains("staring:     2 people"), "{stdout}");
    let column = |name: &str| header.iter().position(|h| h == name).unwrap();
    let (id, time, gaze_z) = (column("id"), column("time"), column("gaze_z"));
    let follow = column("follow_x");
    let following: Vec<&Vec<String>> = rows.iter().filter(|r| !r[follow].is_empty()).collect();
    assert!(!following.is_empty(), "nobody followed: {stdout}");
    for row in &following {
        let point: Vec<f64> = row[follow..follow + 3]
            .iter()
            .map(|v| v.parse().unwrap())
            .collect();
        assert!(
            (point[0] - 5.0).abs() < 1e-4
                && (point[1] - 5.0).abs() < 1e-4
                && (point[2] - 8.0).abs() < 1e-4,
            "{row:?}"
        );
        // A starer does not follow while it stares (person 2 may after 5 s).
        let t: f64 = row[time].parse().unwrap();
        assert!(
            row[id] != "1" && (row[id] != "2" || t > 5.0),
            "a starer follows: {row:?}"
        );
    }
    // Following is a glance, not a stare: most person-frames follow nobody.
    assert!(following.len() * 4 < rows.len(), "{}", following.len());
    // The starers look up, person 2 only until 5 s (its track ends at 10.44 s).
    let up = |who: &str, from: f64, to: f64| -> (usize, usize) {
        let mine: Vec<&Vec<String>> = rows
            .iter()
            .filter(|r| r[id] == who)
            .filter(|r| (from..to).contains(&r[time].parse::<f64>().unwrap()))
            .collect();
        let up = mine
            .iter()
            .filter(|r| r[gaze_z].parse::<f64>().unwrap() > 0.3)
            .count();
        (up, mine.len())
    };
    let (one_up, one) = up("1", 1.0, 40.0);
    assert!(one > 0 && one_up * 10 >= one * 9, "{one_up} of {one}");
    let (two_up, two) = up("2", 6.0, 40.0);
    assert!(
        two >= 30 && two_up * 2 < two,
        "person 2 still looks up: {two_up} of {two}"
    );
    let (two_up, two) = up("2", 1.0, 5.0);
    assert!(two > 0 && two_up * 10 >= two * 9, "{two_up} of {two}");
}

#[test]
fn annotate_refuses_bad_stares_by_name_and_leaves_nothing() {
    let input = data("pedestrians/ucy_zara01.csv");
    let directory = tempfile::tempdir().unwrap();
    let out = directory.path().join("gaze.csv");
    let base = annotate_args(&input, &out);
    for (stare, why) in [
        ("1:5,5", "3"),
        ("x:1,2,3", "person id"),
        ("1:1,2,nan", "coordinate"),
        ("1:1,2,3:5-2", "ends before it starts"),
        ("1:1,2,3:a-b", "window"),
        ("1:1,2,3:4-5:6", "too many"),
        ("999999:1,2,3", "no person 999999"),
    ] {
        let output = crowdgaze(&[&base[..], &["--stare", stare]].concat());
        let stderr = text(&output.stderr);
        assert!(!output.status.success(), "{stare} accepted");
        assert!(stderr.contains("--stare"), "{stare}: {stderr}");
        assert!(stderr.contains(why), "{stare}: '{why}' not in {stderr}");
        assert!(entries(directory.path()).is_empty(), "{stare}: output left");
        println!("{}", stderr.lines().next().unwrap_or(""));
    }
    // --follow-strength without --follow is refused, naming --follow.
    let output = crowdgaze(&[&base[..], &["--follow-strength", "gallup"]].concat());
    assert!(!output.status.success());
    assert!(text(&output.stderr).contains("--follow"));
}
