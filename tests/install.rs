//! `scripts/install PREFIX` into a temporary prefix (a release build), then programs built
//! against the installed tree only: the CMake consumer (`c_examples/cmake_consumer`, with
//! `crowdgaze::shared` and `crowdgaze::static`), the same program by the install page's
//! pkg-config build lines, and the OpenSceneGraph example (`c_examples/osg`) rendered under
//! Xvfb, whose PNG frames are checked: there, not blank, changing, and the red-nosed
//! bystander's head turning on the images as its logged head rotation says.
//!
//! Needs cmake, pkg-config, OpenSceneGraph 3.6, xvfb-run and Mesa (`scripts/setup` installs
//! them): where one is missing, the test that needs it fails and names it.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::sync::OnceLock;

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

/// The SONAME's version, the part of the version that breaks the ABI: `0.MINOR` below 1.0,
/// `MAJOR` from 1.0 (as `build.rs` sets it).
fn abi() -> String {
    match env!("CARGO_PKG_VERSION_MAJOR") {
        "0" => format!("0.{}", env!("CARGO_PKG_VERSION_MINOR")),
        major => major.to_owned(),
    }
}

fn work() -> PathBuf {
    Path::new(env!("CARGO_TARGET_TMPDIR")).join("install")
}

fn run(command: &mut Command) -> Output {
    let output = command
        .output()
        .unwrap_or_else(|e| panic!("run {command:?}: {e}"));
    assert!(
        output.status.success(),
        "{command:?} failed ({:?})\nstdout:\n{}\nstderr:\n{}",
        output.status,
        String::from_utf8_lossy(&output.stdout),
        String::from_utf8_lossy(&output.stderr)
    );
    output
}

fn stdout(output: &Output) -> String {
    String::from_utf8_lossy(&output.stdout).into_owned()
}

/// Fails, naming `tool`, unless `tool args` runs.
fn need(tool: &str, args: &[&str]) {
    let found = Command::new(tool)
        .args(args)
        .output()
        .is_ok_and(|o| o.status.success());
    assert!(
        found,
        "{tool} is missing: scripts/setup installs it (scripts/test runs scripts/setup)"
    );
}

/// The prefix `scripts/install` filled, once for all the tests of this file.
fn prefix() -> &'static Path {
    static PREFIX: OnceLock<PathBuf> = OnceLock::new();
    PREFIX.get_or_init(|| {
        let prefix = work().join("prefix");
        let _ = std::fs::remove_dir_all(&prefix);
        std::fs::create_dir_all(work()).expect("work dir");
        let output = run(Command::new(root().join("scripts/install")).arg(&prefix));
        assert!(stdout(&output).contains("installed crowdgaze"));
        prefix
    })
}

#[test]
#[cfg_attr(miri, ignore)]
fn install_puts_headers_libraries_and_package_files_under_the_prefix() {
    let prefix = prefix();
    let version = env!("CARGO_PKG_VERSION");
    let abi = abi();
    let lib = prefix.join("lib");

    for (installed, source) in [
        ("include/crowdgaze.h", "include/crowdgaze.h"),
        ("include/crowdgaze.hpp", "bindings/cpp/crowdgaze.hpp"),
    ] {
        assert_eq!(
            std::fs::read(prefix.join(installed)).expect(installed),
            std::fs::read(root().join(source)).expect(source),
            "{installed}"
        );
    }
    let real = lib.join(format!("libcrowdgaze.so.{version}"));
    assert!(real.is_file() && !real.is_symlink());
    assert_eq!(
        std::fs::read_link(lib.join(format!("libcrowdgaze.so.{abi}"))).unwrap(),
        PathBuf::from(format!("libcrowdgaze.so.{version}"))
    );
    assert_eq!(
        std::fs::read_link(lib.join("libcrowdgaze.so")).unwrap(),
        PathBuf::from(format!("libcrowdgaze.so.{abi}"))
    );
    let dynamic = stdout(&run(Command::new("readelf").arg("-d").arg(&real)));
    assert!(
        dynamic.contains(&format!("Library soname: [libcrowdgaze.so.{abi}]")),
        "SONAME:\n{dynamic}"
    );
    let archive = std::fs::read(lib.join("libcrowdgaze.a")).expect("libcrowdgaze.a");
    assert!(archive.starts_with(b"!<arch>\n"));
    // Every exported C function is in the installed shared library.
    let symbols = stdout(&run(Command::new("nm")
        .args(["-D", "--defined-only"])
        .arg(&real)));
    for name in [
        "cg_crowd_create",
        "cg_crowd_step",
        "cg_view_blender_evaluate",
    ] {
        assert!(symbols.contains(name), "{name} not exported");
    }

    let pc = std::fs::read_to_string(lib.join("pkgconfig/crowdgaze.pc")).expect("crowdgaze.pc");
    assert!(
        pc.contains(&format!("prefix={}\n", prefix.display())),
        "{pc}"
    );
    assert!(pc.contains(&format!("Version: {version}\n")), "{pc}");
    assert!(pc.contains("Libs: -L${libdir} -lcrowdgaze\n"), "{pc}");
    assert!(pc.contains("Libs.private: ${native_static_libs}\n"), "{pc}");
    let native = pc
        .lines()
        .find_map(|l| l.strip_prefix("native_static_libs="))
        .expect("native_static_libs");
    assert!(
        native.split_whitespace().all(|f| f.starts_with("-l")) && native.contains("-lc"),
        "native libs {native:?}"
    );

    let cmake = lib.join("cmake/crowdgaze");
    let config = std::fs::read_to_string(cmake.join("crowdgazeConfig.cmake")).unwrap();
    for needle in [
        "add_library(crowdgaze::shared SHARED IMPORTED)",
        "add_library(crowdgaze::static STATIC IMPORTED)",
        &format!("libcrowdgaze.so.{version}"),
        &format!("IMPORTED_SONAME \"libcrowdgaze.so.{abi}\""),
    ] {
        assert!(config.contains(needle), "{needle} missing from the config");
    }
    let config_version =
        std::fs::read_to_string(cmake.join("crowdgazeConfigVersion.cmake")).unwrap();
    assert!(config_version.contains(&format!("set(PACKAGE_VERSION \"{version}\")")));
}

/// Checks the consumer program's output (c_examples/cmake_consumer/main.c).
fn check_consumer(program: &Path) {
    let output = run(&mut Command::new(program));
    let text = stdout(&output);
    assert!(
        text.contains(&format!("crowdgaze {}", env!("CARGO_PKG_VERSION"))),
        "{text}"
    );
    assert!(text.contains("character 0 looks at 1"), "{text}");
    assert_eq!(text.lines().last(), Some("ok"), "{text}");
}

fn needed_libraries(program: &Path) -> String {
    stdout(&run(Command::new("readelf").arg("-d").arg(program)))
}

#[test]
#[cfg_attr(miri, ignore)]
fn cmake_consumer_builds_against_the_installed_package() {
    need("cmake", &["--version"]);
    let build = work().join("cmake_consumer");
    let _ = std::fs::remove_dir_all(&build);
    let configure = run(Command::new("cmake")
        .arg("-S")
        .arg(root().join("c_examples/cmake_consumer"))
        .arg("-B")
        .arg(&build)
        .arg(format!("-DCMAKE_PREFIX_PATH={}", prefix().display())));
    assert!(
        stdout(&configure).contains(&format!("crowdgaze {}", env!("CARGO_PKG_VERSION"))),
        "{}",
        stdout(&configure)
    );
    run(Command::new("cmake").arg("--build").arg(&build));
    let shared = build.join("consumer_shared");
    let statik = build.join("consumer_static");
    check_consumer(&shared);
    check_consumer(&statik);
    assert!(needed_libraries(&shared).contains(&format!("[libcrowdgaze.so.{}]", abi())));
    assert!(!needed_libraries(&statik).contains("libcrowdgaze"));

    // A version this package cannot satisfy is refused (0.x: the minor must match).
    let project = work().join("cmake_version");
    std::fs::create_dir_all(&project).unwrap();
    std::fs::write(
        project.join("CMakeLists.txt"),
        "cmake_minimum_required(VERSION 3.16)\nproject(v LANGUAGES C)\n\
         find_package(crowdgaze 0.99 CONFIG)\n\
         message(STATUS \"found: ${crowdgaze_FOUND}\")\n",
    )
    .unwrap();
    let refused = run(Command::new("cmake")
        .arg("-S")
        .arg(&project)
        .arg("-B")
        .arg(project.join("build"))
        .arg(format!("-DCMAKE_PREFIX_PATH={}", prefix().display())));
    assert!(
        stdout(&refused).contains("found: 0"),
        "{}",
        stdout(&refused)
    );
}

#[test]
#[cfg_attr(miri, ignore)]
fn pkg_config_build_lines_of_the_install_page_work() {
    need("pkg-config", &["--version"]);
    let build = work().join("pkg_config");
    std::fs::create_dir_all(&build).unwrap();
    let source = root().join("c_examples/cmake_consumer/main.c");
    // The two build lines of the install page (docs/install.md), as written there: shared,
    // then static. The shared one gets the rpath the page says to add outside the loader's
    // search path.
    let page = std::fs::read_to_string(root().join("docs/install.md")).unwrap();
    let lines: Vec<String> = page
        .replace("\\\n", " ")
        .lines()
        .filter(|line| line.starts_with("cc app.c") && line.contains("pkg-config"))
        .map(|line| line.split_whitespace().collect::<Vec<_>>().join(" "))
        .collect();
    assert_eq!(
        lines.len(),
        2,
        "docs/install.md's two pkg-config lines: {lines:?}"
    );
    let rpath = " -Wl,-rpath,\"$(pkg-config --variable=libdir crowdgaze)\"";
    for ((line, name), extra) in lines
        .iter()
        .zip(["app_shared", "app_static"])
        .zip([rpath, ""])
    {
        let command = line
            .replace("app.c", &source.display().to_string())
            .replace("-o app", &format!("-o {}", build.join(name).display()));
        run(Command::new("sh")
            .arg("-c")
            .arg(format!("{command}{extra} -lm"))
            .env("PKG_CONFIG_PATH", prefix().join("lib/pkgconfig")));
        check_consumer(&build.join(name));
    }
    assert!(needed_libraries(&build.join("app_shared")).contains("libcrowdgaze.so"));
    assert!(!needed_libraries(&build.join("app_static")).contains("libcrowdgaze"));
    let version = run(Command::new("pkg-config")
        .args(["--modversion", "crowdgaze"])
        .env("PKG_CONFIG_PATH", prefix().join("lib/pkgconfig")));
    assert_eq!(stdout(&version).trim(), env!("CARGO_PKG_VERSION"));
}

/// One rendered frame and what the program logged about it.
struct Frame {
    path: PathBuf,
    head_yaw: Vec<f64>,
    nose: (f64, f64),
}

fn parse_log(log: &str) -> (usize, Vec<Frame>) {
    let mut observer = None;
    let mut frames: Vec<Frame> = Vec::new();
    for line in log.lines() {
        let words: Vec<&str> = line.split_whitespace().collect();
        match words.first() {
            Some(&"observer") => observer = Some(words[1].parse::<usize>().unwrap()),
            Some(&"frame") => frames.push(Frame {
                path: PathBuf::from(words[5]),
                head_yaw: Vec::new(),
                nose: (f64::NAN, f64::NAN),
            }),
            Some(&"head") => {
                let frame = frames.last_mut().expect("head after frame");
                assert_eq!(words[1].parse::<usize>().unwrap(), frame.head_yaw.len());
                let q: Vec<f64> = words[3..7].iter().map(|w| w.parse().unwrap()).collect();
                let norm = q.iter().map(|c| c * c).sum::<f64>().sqrt();
                assert!((norm - 1.0).abs() < 1e-3, "head quaternion {q:?}");
                frame.head_yaw.push(words[8].parse().unwrap());
            }
            Some(&"nose") => {
                frames.last_mut().expect("nose after frame").nose =
                    (words[1].parse().unwrap(), words[2].parse().unwrap());
            }
            _ => {}
        }
    }
    (observer.expect("observer line"), frames)
}

struct Image {
    width: usize,
    height: usize,
    rgb: Vec<u8>,
}

fn read_png(path: &Path) -> Image {
    let decoder = png::Decoder::new(std::io::BufReader::new(
        std::fs::File::open(path).unwrap_or_else(|e| panic!("{}: {e}", path.display())),
    ));
    let mut reader = decoder.read_info().expect("PNG header");
    let mut buffer = vec![0; reader.output_buffer_size().expect("size")];
    let info = reader.next_frame(&mut buffer).expect("PNG data");
    assert_eq!(info.bit_depth, png::BitDepth::Eight);
    let channels = match info.color_type {
        png::ColorType::Rgb => 3,
        png::ColorType::Rgba => 4,
        other => panic!("unexpected colour type {other:?}"),
    };
    let (width, height) = (info.width as usize, info.height as usize);
    let mut rgb = Vec::with_capacity(width * height * 3);
    for y in 0..height {
        let row = &buffer[y * info.line_size..];
        for x in 0..width {
            rgb.extend_from_slice(&row[x * channels..x * channels + 3]);
        }
    }
    Image { width, height, rgb }
}

/// Configures and builds `c_examples/osg` against the install; returns its build directory.
fn build_osg_street() -> PathBuf {
    need("cmake", &["--version"]);
    need("xvfb-run", &["--help"]);
    let build = work().join("osg");
    let _ = std::fs::remove_dir_all(&build);
    let configure = Command::new("cmake")
        .arg("-S")
        .arg(root().join("c_examples/osg"))
        .arg("-B")
        .arg(&build)
        .arg("-DCMAKE_BUILD_TYPE=Release")
        .arg(format!("-DCMAKE_PREFIX_PATH={}", prefix().display()))
        .output()
        .expect("run cmake");
    if !configure.status.success() {
        let error = String::from_utf8_lossy(&configure.stderr);
        assert!(
            !error.contains("OpenSceneGraph"),
            "OpenSceneGraph 3.6 is missing: scripts/setup installs libopenscenegraph-dev\n{error}"
        );
        panic!("configuring c_examples/osg failed:\n{error}");
    }
    run(Command::new("cmake").arg("--build").arg(&build));
    build
}

/// Builds `c_examples/osg` (once for the tests of this file) and runs it under Xvfb with
/// the environment `env`, writing 960x540 frames for `seconds` into `frames` of its build
/// directory; returns its log, checked to end with "ok".
fn run_osg_street(env: &[(&str, &str)], frames: &str, seconds: &str) -> String {
    static BUILD: OnceLock<PathBuf> = OnceLock::new();
    let build = BUILD.get_or_init(build_osg_street);
    let frames_dir = build.join(frames);
    let _ = std::fs::remove_dir_all(&frames_dir);
    std::fs::create_dir_all(&frames_dir).unwrap();
    let output = run(Command::new("timeout")
        .arg("600")
        .arg("xvfb-run")
        .args(["-a", "-s", "-screen 0 1280x1024x24"])
        .arg(build.join("osg_street"))
        .arg(&frames_dir)
        .args(["960x540", seconds])
        .envs(env.iter().copied())
        .env("LIBGL_ALWAYS_SOFTWARE", "1"));
    let log = stdout(&output);
    assert!(log.contains("OpenSceneGraph 3.6"), "{log}");
    assert_eq!(log.lines().last(), Some("ok"), "{log}");
    log
}

#[test]
#[cfg_attr(miri, ignore)]
fn osg_street_look_up_shows_the_group_staring_up() {
    let log = run_osg_street(&[("OSG_STREET_SCENE", "look-up")], "look_up", "5");
    let lookers: Vec<usize> = log
        .lines()
        .find_map(|l| l.strip_prefix("lookers "))
        .expect("a lookers line")
        .split_whitespace()
        .map(|w| w.parse().unwrap())
        .collect();
    assert_eq!(lookers.len(), 4, "{log}");
    // (frame's second, looker, pitch) of every "look" line, in order.
    let (_, frames) = parse_log(&log);
    assert_eq!(frames.len(), 5, "one frame per second for 5 s:\n{log}");
    let pitches: Vec<f64> = log
        .lines()
        .filter_map(|l| l.strip_prefix("look "))
        .filter(|l| !l.starts_with("point"))
        .map(|l| l.split_whitespace().nth(2).unwrap().parse().unwrap())
        .collect();
    assert_eq!(pitches.len(), 4 * frames.len(), "{log}");
    // Before 2 s they look about them; from 3 s they all look well up at the point.
    eprintln!("looker head pitches per second: {pitches:?}");
    assert!(pitches[..4].iter().all(|&p| p < 10.0), "{pitches:?}");
    assert!(pitches[8..].iter().all(|&p| p > 15.0), "{pitches:?}");
    // Gaze following is on in this scene: once they stare, passers-by glance at the point.
    let at_point: Vec<u32> = log
        .lines()
        .filter_map(|l| l.strip_prefix("followers "))
        .map(|l| l.split_whitespace().next().unwrap().parse().unwrap())
        .collect();
    eprintln!("characters glancing at the group's point, per second: {at_point:?}");
    assert_eq!(at_point.len(), frames.len(), "{log}");
    assert!(at_point[..2].iter().all(|&n| n == 0), "{at_point:?}");
    assert!(at_point[2..].iter().any(|&n| n > 0), "{at_point:?}");
    // The point's mark is on every image, and so are the people (not blank).
    for frame in &frames {
        let image = read_png(&frame.path);
        let marks = image
            .rgb
            .chunks(3)
            .filter(|p| p[0] == 255 && (130..=150).contains(&p[1]) && p[2] <= 10)
            .count();
        assert!(
            marks >= 12,
            "{}: {marks} px of the mark",
            frame.path.display()
        );
        let colours: BTreeSet<&[u8]> = image.rgb.chunks(3).collect();
        assert!(colours.len() > 200, "{} colours only", colours.len());
    }
}

#[test]
#[cfg_attr(miri, ignore)]
fn osg_street_renders_heads_turning() {
    let log = run_osg_street(&[], "frames", "8");
    let (observer, frames) = parse_log(&log);
    assert_eq!(frames.len(), 8, "one frame per second for 8 s:\n{log}");

    // The logged heads: many characters turn their heads, the observer a lot.
    let characters = frames[0].head_yaw.len();
    assert!(characters >= 10);
    let mut turned = 0;
    for c in 0..characters {
        let yaws: Vec<f64> = frames.iter().map(|f| f.head_yaw[c]).collect();
        let range = yaws.iter().cloned().fold(f64::MIN, f64::max)
            - yaws.iter().cloned().fold(f64::MAX, f64::min);
        if range > 10.0 {
            turned += 1;
        }
    }
    let observer_yaws: Vec<f64> = frames.iter().map(|f| f.head_yaw[observer]).collect();
    eprintln!(
        "{turned} of {characters} heads turned > 10 degrees; observer yaws {observer_yaws:?}"
    );
    assert!(turned >= characters / 3, "only {turned} heads turned");
    assert!(
        observer_yaws[0] > 10.0,
        "the observer first looks left: {observer_yaws:?}"
    );
    assert!(
        observer_yaws[7] < -45.0,
        "then right, after the walker: {observer_yaws:?}"
    );

    // The images: there, sized, not blank, different from one frame to the next.
    let images: Vec<Image> = frames.iter().map(|f| read_png(&f.path)).collect();
    let mut histogram: BTreeMap<[u8; 3], usize> = BTreeMap::new();
    for image in &images {
        assert_eq!((image.width, image.height), (960, 540));
        histogram.clear();
        for pixel in image.rgb.chunks(3) {
            *histogram.entry([pixel[0], pixel[1], pixel[2]]).or_default() += 1;
        }
        let pixels = image.width * image.height;
        let commonest = histogram.values().max().copied().unwrap_or(0);
        assert!(histogram.len() > 200, "{} colours only", histogram.len());
        assert!(commonest < pixels / 2, "one colour covers half the image");
    }
    for pair in images.windows(2) {
        let changed = pair[0]
            .rgb
            .chunks(3)
            .zip(pair[1].rgb.chunks(3))
            .filter(|(a, b)| a != b)
            .count();
        assert!(
            changed > pair[0].width * pair[0].height / 100,
            "only {changed} pixels changed between frames"
        );
    }

    // The red nose on the images is where the program says the head put it, and it moves as
    // the head turns.
    let mut seen = Vec::new();
    for (frame, image) in frames.iter().zip(&images) {
        let (mut count, mut sum_x, mut sum_y) = (0usize, 0.0, 0.0);
        for (i, pixel) in image.rgb.chunks(3).enumerate() {
            if pixel[0] >= 200 && pixel[1] <= 40 && pixel[2] <= 40 {
                count += 1;
                sum_x += (i % image.width) as f64 + 0.5;
                sum_y += (i / image.width) as f64 + 0.5;
            }
        }
        if count < 12 {
            continue; // hidden behind a passer-by in this frame
        }
        let centre = (sum_x / count as f64, sum_y / count as f64);
        let error = ((centre.0 - frame.nose.0).powi(2) + (centre.1 - frame.nose.1).powi(2)).sqrt();
        assert!(
            error < 4.0,
            "{}: red nose at {centre:?} ({count} px), logged at {:?}",
            frame.path.display(),
            frame.nose
        );
        seen.push(centre);
    }
    assert!(
        seen.len() >= 5,
        "the red nose was visible in {} frames",
        seen.len()
    );
    let xs: Vec<f64> = seen.iter().map(|c| c.0).collect();
    let travel =
        xs.iter().cloned().fold(f64::MIN, f64::max) - xs.iter().cloned().fold(f64::MAX, f64::min);
    assert!(
        travel > 8.0,
        "the nose moved {travel:.1} px across the frames: {seen:?}"
    );
}
