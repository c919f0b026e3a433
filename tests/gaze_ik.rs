//! Behaviour of the gaze IK through the crate's Rust API: convergence, recruitment bands,
//! eyes → head → spine timing, moving and jumping targets, target switches, deactivation,
//! joint limits and speed limits on every frame, degenerate targets, custom chains and
//! animated base poses.

use std::f32::consts::PI;

use crowdgaze::ik::spatial::{self, eye_rays};
use crowdgaze::ik::{
    ChainJoint, CharacterTransform, GazeChain, GazeConfig, GazeInput, GazeMotion, GazePhase,
    GazeRequest, JointGroup, JointLimits, JointRole, TurnSide,
};
use crowdgaze::math::random::{stream, Purpose, Random};
use glam::{Quat, Vec3};

const EYE_HEIGHT: f32 = 1.62;

fn degrees(value: f32) -> f32 {
    value.to_radians()
}

/// A character driven frame by frame, recording every frame.
struct Character {
    chain: GazeChain,
    config: GazeConfig,
    motion: GazeMotion,
    base: Vec<Quat>,
    transform: CharacterTransform,
    random: Random,
    frames: Vec<Frame>,
}

#[derive(Clone)]
struct Frame {
    deltas: Vec<Quat>,
    origins: [Vec3; 2],
    directions: [Vec3; 2],
    phase: GazePhase,
    dt: f32,
}

impl Character {
    fn new(chain: GazeChain) -> Character {
        let base = chain.joints().iter().map(|joint| joint.rest).collect();
        Character {
            motion: GazeMotion::new(&chain),
            chain,
            config: GazeConfig::default(),
            base,
            transform: CharacterTransform::IDENTITY,
            random: stream(7, Purpose::GazeTiming, 0),
            frames: Vec::new(),
        }
    }

    fn human() -> Character {
        Character::new(GazeChain::human(Vec3::Y, Vec3::Z))
    }

    fn step(&mut self, request: Option<GazeRequest>, dt: f32) -> &Frame {
        let input = GazeInput {
            character: self.transform,
            base: &self.base,
            request,
            dt,
        };
        self.motion
            .update(&self.chain, &self.config, &input, &mut self.random)
            .expect("update succeeds");
        self.frames.push(Frame {
            deltas: self.motion.deltas().to_vec(),
            origins: self.motion.eye_origins(),
            directions: self.motion.eye_directions(),
            phase: self.motion.phase(),
            dt,
        });
        self.frames.last().unwrap()
    }

    fn run(&mut self, request: Option<GazeRequest>, seconds: f32, dt: f32) -> &Frame {
        let frames = (seconds / dt).ceil() as usize;
        for _ in 0..frames.max(1) {
            self.step(request, dt);
        }
        self.frames.last().unwrap()
    }

    fn group(&self, index: usize) -> JointGroup {
        self.chain.joints()[index].role.group()
    }
}

/// A point `distance` metres from the character's eye height, `yaw` degrees to its left
/// (Y up, facing +Z), `pitch` degrees up.
fn around(yaw: f32, pitch: f32, distance: f32) -> Vec3 {
    let (yaw, pitch) = (degrees(yaw), degrees(pitch));
    Vec3::new(
        yaw.sin() * pitch.cos() * distance,
        EYE_HEIGHT + pitch.sin() * distance,
        yaw.cos() * pitch.cos() * distance,
    )
}

/// Largest angle (radians) between an eye ray and the direction from that eye to `target`.
fn eye_error(frame: &Frame, target: Vec3) -> f32 {
    (0..2)
        .map(|eye| {
            let wanted = (target - frame.origins[eye]).normalize();
            frame.directions[eye].angle_between(wanted)
        })
        .fold(0.0, f32::max)
}

fn angle(a: Quat, b: Quat) -> f32 {
    2.0 * a.dot(b).abs().min(1.0).acos()
}

#[test]
fn eye_rays_converge_on_reachable_targets() {
    for (yaw, pitch, distance) in [
        (0.0, 0.0, 3.0),
        (10.0, -5.0, 1.0),
        (25.0, 10.0, 2.0),
        (-45.0, 0.0, 5.0),
        (70.0, -20.0, 1.5),
        (-110.0, 15.0, 10.0),
        (130.0, 0.0, 4.0),
    ] {
        let mut character = Character::human();
        let target = around(yaw, pitch, distance);
        let frame = character.run(Some(GazeRequest::at(1, target)), 5.0, 1.0 / 30.0);
        assert_eq!(frame.phase, GazePhase::Holding);
        let error = eye_error(frame, target);
        assert!(
            error < degrees(0.5),
            "target at yaw {yaw}, pitch {pitch}, {distance} m: eye error {}°",
            error.to_degrees()
        );
    }
}

#[test]
fn small_shifts_move_only_the_eyes() {
    let mut character = Character::human();
    let target = around(12.0, 3.0, 2.0);
    character.run(Some(GazeRequest::at(1, target)), 2.0, 1.0 / 60.0);
    for frame in &character.frames {
        assert!(frame.deltas[..8].iter().all(|q| *q == Quat::IDENTITY));
    }
    let last = character.frames.last().unwrap();
    assert!(last.deltas[8] != Quat::IDENTITY && last.deltas[9] != Quat::IDENTITY);
    assert!(eye_error(last, target) < degrees(0.5));
}

#[test]
fn medium_shifts_leave_the_spine_alone() {
    let mut character = Character::human();
    let target = around(-25.0, 0.0, 3.0);
    character.run(Some(GazeRequest::at(1, target)), 2.0, 1.0 / 60.0);
    for frame in &character.frames {
        assert!(frame.deltas[..5].iter().all(|q| *q == Quat::IDENTITY));
    }
    let last = character.frames.last().unwrap();
    assert!(last.deltas[5..8]
        .iter()
        .all(|q| angle(*q, Quat::IDENTITY) > degrees(0.5)));
    assert!(eye_error(last, target) < degrees(0.5));
}

/// Frame indices (within `frames`) of onset and arrival of the eyes, the head and the
/// first spine joint over one shift that starts at `frames[0]` and ends settled at
/// `frames.last()`.
fn onsets_and_arrivals(
    character: &Character,
    frames: &[Frame],
    target: Vec3,
) -> [(Option<usize>, Option<usize>); 3] {
    let start = &frames[0];
    let settled = frames.last().unwrap();
    let mean = |frame: &Frame| (frame.directions[0] + frame.directions[1]).normalize();
    // Eyes: onset when the gaze has moved 5% of its initial error; arrival when each eye is
    // on the target or at its limit.
    let initial_error = mean(start).angle_between((target - start.origins[0]).normalize());
    let eye_limit = character.chain.joints()[8].limits;
    let eyes_onset = frames
        .iter()
        .position(|f| mean(f).angle_between(mean(start)) > 0.05 * initial_error);
    let eyes_arrival = frames.iter().position(|f| {
        eye_error(f, target) < degrees(0.5)
            || (8..10)
                .all(|i| eye_limit.swing_twist_angles(f.deltas[i]).0 > eye_limit.max_swing() - 1e-3)
    });
    let body = |index: usize| {
        let travel = angle(start.deltas[index], settled.deltas[index]);
        if travel < degrees(0.5) {
            return (None, None);
        }
        let onset = frames
            .iter()
            .position(|f| angle(start.deltas[index], f.deltas[index]) > 0.05 * travel);
        let arrival = frames
            .iter()
            .position(|f| angle(f.deltas[index], settled.deltas[index]) < 0.02 * travel);
        (onset, arrival)
    };
    [(eyes_onset, eyes_arrival), body(7), body(0)]
}

#[test]
fn eyes_lead_then_head_then_spine_on_every_shift() {
    let dt = 1.0 / 120.0;
    let mut character = Character::human();
    // (key, target, seconds before the next shift)
    let shifts = [
        (1, around(60.0, 0.0, 3.0), 3.0),
        (2, around(-50.0, 10.0, 2.0), 0.12), // interrupted mid-shift
        (3, around(100.0, -10.0, 4.0), 4.0),
        (4, around(-20.0, 0.0, 3.0), 3.0),
        (5, around(160.0, 5.0, 3.0), 4.0),
    ];
    let mut first = 0;
    for (key, target, seconds) in shifts {
        character.run(Some(GazeRequest::at(key, target)), seconds, dt);
        let frames = &character.frames[first..];
        first = character.frames.len();
        if seconds < 1.0 {
            continue; // not settled: checked as the start of the next shift
        }
        let [(eyes_on, eyes_at), (head_on, head_at), (spine_on, spine_at)] =
            onsets_and_arrivals(&character, frames, target);
        let (eyes_on, eyes_at) = (eyes_on.unwrap(), eyes_at.unwrap());
        let (head_on, head_at) = (head_on.unwrap(), head_at.unwrap());
        assert!(
            eyes_on < head_on,
            "shift {key}: eyes start {eyes_on}, head {head_on}"
        );
        assert!(
            eyes_at < head_at,
            "shift {key}: eyes arrive {eyes_at}, head {head_at}"
        );
        if let (Some(spine_on), Some(spine_at)) = (spine_on, spine_at) {
            assert!(
                head_on < spine_on,
                "shift {key}: head starts {head_on}, spine {spine_on}"
            );
            assert!(
                head_at < spine_at,
                "shift {key}: head arrives {head_at}, spine {spine_at}"
            );
        } else {
            assert_eq!(key, 4, "only the 20° shift may leave the spine still");
        }
    }
}

#[test]
fn activation_time_follows_the_formula_and_its_cap() {
    for (yaw, ratio) in [(90.0, 1.0), (60.0, 0.5), (150.0, 0.1), (45.0, 0.02)] {
        let mut character = Character::human();
        let target = around(yaw, 0.0, 3.0);
        let request = GazeRequest {
            interest_ratio: ratio,
            ..GazeRequest::at(1, target)
        };
        character.step(Some(request), 1.0 / 30.0);
        // θ_head: the head's rotation in the chain root's frame from rest to the solution.
        let mut deltas = vec![Quat::IDENTITY; 10];
        spatial::solve(
            &character.chain,
            &character.config.spatial,
            &CharacterTransform::IDENTITY,
            &character.base,
            target,
            target,
            &mut TurnSide::default(),
            &mut deltas,
        )
        .unwrap();
        let head: Quat = deltas[..8].iter().fold(Quat::IDENTITY, |acc, q| acc * *q);
        let head_angle = angle(Quat::IDENTITY, head);
        let expected = (head_angle / (2.0 * PI * ratio)).clamp(0.2, 2.0);
        let actual = character.motion.activation_time();
        assert!(
            (actual - expected).abs() < 1e-4,
            "yaw {yaw}, ratio {ratio}: t_a {actual} vs {expected}"
        );
        if ratio <= 0.1 {
            assert_eq!(actual, 2.0, "capped at 2 s");
        }
        // The groups last t_a/2, t_a and 2 t_a.
        let durations = character.motion.group_durations();
        assert_eq!(durations, [0.5 * actual, actual, 2.0 * actual]);
    }
}

#[test]
fn the_ease_is_exact_at_both_ends() {
    let dt = 1.0 / 30.0;
    let mut character = Character::human();
    let target = around(80.0, 0.0, 3.0);
    // Start: the restart frame keeps the start pose exactly.
    let frame = character.step(Some(GazeRequest::at(1, target)), dt).clone();
    assert!(frame.deltas.iter().all(|q| *q == Quat::IDENTITY));
    // End: once each group's time is over, its joints are exactly on the spatial solution.
    let mut solution = vec![Quat::IDENTITY; 10];
    spatial::solve(
        &character.chain,
        &character.config.spatial,
        &CharacterTransform::IDENTITY,
        &character.base,
        target,
        target,
        &mut TurnSide::default(),
        &mut solution,
    )
    .unwrap();
    let t_a = character.motion.activation_time();
    let mut elapsed = 0.0;
    while elapsed < 2.0 * t_a + dt {
        character.step(Some(GazeRequest::at(1, target)), dt);
        elapsed += dt;
        let deltas = character.motion.deltas();
        for index in 0..8 {
            let duration = character.motion.group_durations()[character.group(index).index()];
            if character.motion.elapsed() >= duration {
                assert_eq!(deltas[index], solution[index], "joint {index} at {elapsed}");
            } else {
                assert_ne!(deltas[index], solution[index], "joint {index} at {elapsed}");
            }
        }
    }
    assert_eq!(character.motion.phase(), GazePhase::Holding);
}

#[test]
fn a_moving_target_is_followed() {
    let dt = 1.0 / 30.0;
    let mut character = Character::human();
    // A pedestrian crossing 2.5 m ahead at 1.4 m/s, from 3 m to the left to 3 m to the right.
    let position = |time: f32| Vec3::new(3.0 - 1.4 * time, EYE_HEIGHT, 2.5);
    let mut time = 0.0;
    let mut previous_yaw = f32::INFINITY;
    while time < 6.0 / 1.4 {
        let target = position(time);
        let frame = character.step(Some(GazeRequest::at(1, target)), dt).clone();
        if time > 1.0 {
            assert_eq!(frame.phase, GazePhase::Holding, "no restart at {time}");
            assert!(
                eye_error(&frame, target) < degrees(0.5),
                "eyes on target at {time}"
            );
            // The head follows: its yaw decreases as the target goes left to right.
            let (_, yaw) = character.chain.joints()[7]
                .limits
                .swing_twist_angles(frame.deltas[7]);
            assert!(yaw <= previous_yaw + 1e-6, "head yaw increases at {time}");
            previous_yaw = yaw;
        }
        time += dt;
    }
    assert!(previous_yaw < 0.0, "the head ends turned right");
}

#[test]
fn a_jumping_target_restarts_the_shift() {
    let dt = 1.0 / 30.0;
    let mut character = Character::human();
    let first = around(40.0, 0.0, 3.0);
    character.run(Some(GazeRequest::at(1, first)), 3.0, dt);
    assert_eq!(character.motion.phase(), GazePhase::Holding);
    let before = character.motion.deltas().to_vec();
    // Same key, but the point jumps 3 m: restart from the current pose.
    let second = around(-40.0, 0.0, 3.0);
    character.step(Some(GazeRequest::at(1, second)), dt);
    assert_eq!(character.motion.phase(), GazePhase::Shifting);
    assert_eq!(character.motion.elapsed(), 0.0);
    assert_eq!(character.motion.deltas(), &before[..]);
    let frame = character.run(Some(GazeRequest::at(1, second)), 3.0, dt);
    assert!(eye_error(frame, second) < degrees(0.5));
    // A small move does not restart.
    let nudged = second + Vec3::X * 0.1;
    character.step(Some(GazeRequest::at(1, nudged)), dt);
    assert_eq!(character.motion.phase(), GazePhase::Holding);
}

#[test]
fn a_new_target_is_reached_without_passing_through_rest() {
    let dt = 1.0 / 60.0;
    let mut character = Character::human();
    character.run(Some(GazeRequest::at(1, around(70.0, 0.0, 3.0))), 3.0, dt);
    let held = character.motion.deltas().to_vec();
    let first_new = character.frames.len();
    let target = around(-70.0, 0.0, 3.0);
    character.run(Some(GazeRequest::at(2, target)), 3.0, dt);
    let frames = &character.frames[first_new..];
    assert_eq!(
        frames[0].deltas, held,
        "the new shift starts from the current pose"
    );
    // Every body joint's yaw goes straight from left to right: monotonic, never parked at 0.
    for index in 0..8 {
        let limits = character.chain.joints()[index].limits;
        let yaws: Vec<f32> = frames
            .iter()
            .map(|f| limits.swing_twist_angles(f.deltas[index]).1)
            .collect();
        assert!(
            yaws[0] > 0.0 && *yaws.last().unwrap() < 0.0,
            "joint {index}"
        );
        assert!(
            yaws.windows(2).all(|w| w[1] <= w[0] + 1e-6),
            "joint {index} not monotonic"
        );
        let at_zero = yaws.iter().filter(|y| y.abs() < 1e-4).count();
        assert!(
            at_zero <= 1,
            "joint {index} rests at 0 for {at_zero} frames"
        );
    }
    assert!(eye_error(frames.last().unwrap(), target) < degrees(0.5));
}

#[test]
fn deactivation_returns_to_the_base_within_t_d() {
    let dt = 1.0 / 30.0;
    let mut draws = Vec::new();
    for index in 0..4 {
        let mut character = Character::human();
        character.random = stream(11, Purpose::GazeTiming, index);
        character.run(Some(GazeRequest::at(1, around(-120.0, 10.0, 2.0))), 4.0, dt);
        assert!(character
            .motion
            .deltas()
            .iter()
            .all(|q| *q != Quat::IDENTITY));
        character.step(None, dt);
        assert_eq!(character.motion.phase(), GazePhase::Returning);
        let t_d = character.motion.deactivation_time();
        assert!((0.5..1.5).contains(&t_d), "t_d {t_d}");
        draws.push(t_d);
        let mut elapsed = 0.0;
        while elapsed < t_d - 1e-6 {
            character.step(None, dt);
            elapsed += dt;
        }
        assert_eq!(
            character.motion.phase(),
            GazePhase::Idle,
            "idle after {elapsed} s"
        );
        assert!(character
            .motion
            .deltas()
            .iter()
            .all(|q| *q == Quat::IDENTITY));
        // The same seed and character draw the same t_d.
        let mut again = Character::human();
        again.random = stream(11, Purpose::GazeTiming, index);
        again.run(Some(GazeRequest::at(1, around(-120.0, 10.0, 2.0))), 4.0, dt);
        again.step(None, dt);
        assert_eq!(again.motion.deactivation_time(), t_d);
    }
    draws.dedup();
    assert_eq!(draws.len(), 4, "each character draws its own t_d");
}

/// Checks every recorded frame: finite unit deltas, limits, and no joint turning faster
/// than its group's speed limit.
fn check_every_frame(character: &Character) {
    let speeds = character.config.timing.max_joint_speed;
    let mut previous: Option<&Frame> = None;
    for (number, frame) in character.frames.iter().enumerate() {
        for (index, delta) in frame.deltas.iter().enumerate() {
            assert!(
                delta.is_finite() && (delta.length() - 1.0).abs() < 1e-4,
                "frame {number} joint {index}: {delta:?}"
            );
            let limits = character.chain.joints()[index].limits;
            assert!(
                limits.contains(*delta, 1e-4),
                "frame {number} joint {index} outside its limits: {:?}",
                limits.swing_twist_angles(*delta)
            );
            if let Some(previous) = previous {
                let step = angle(previous.deltas[index], *delta);
                let allowed = speeds[character.group(index).index()] * frame.dt;
                assert!(
                    step <= allowed * 1.01 + 1e-5,
                    "frame {number} joint {index} jumps {}° (max {}°)",
                    step.to_degrees(),
                    allowed.to_degrees()
                );
            }
        }
        for eye in 0..2 {
            assert!(frame.origins[eye].is_finite() && frame.directions[eye].is_finite());
        }
        previous = Some(frame);
    }
}

fn sweeps(character: &mut Character) {
    let dt = 1.0 / 30.0;
    let eye = character.chain.rest_eye_position();
    let up = character.chain.eye_up();
    let forward = character.chain.eye_forward();
    let left = up.cross(forward);
    // Twice around the character, at eye height, 1.5 m away, 90°/s.
    let mut time = 0.0;
    while time < 8.0 {
        let yaw = degrees(90.0) * time;
        let target = eye + (forward * yaw.cos() + left * yaw.sin()) * 1.5;
        character.step(Some(GazeRequest::at(1, target)), dt);
        time += dt;
    }
    // Over the head: a vertical circle through straight above and straight behind.
    time = 0.0;
    while time < 8.0 {
        let pitch = degrees(90.0) * time;
        let target = eye + (forward * pitch.cos() + up * pitch.sin()) * 1.0;
        character.step(Some(GazeRequest::at(2, target)), dt);
        time += dt;
    }
    // Straight through the eye, from 1 m ahead to 1 m behind, landing exactly on it.
    for step in 0..=40 {
        let along = 1.0 - step as f32 * 0.05;
        character.step(Some(GazeRequest::at(3, eye + forward * along)), dt);
    }
    // And a target that sits at the eye.
    character.run(Some(GazeRequest::at(4, eye)), 1.0, dt);
    // Behind, jittering across straight behind.
    for step in 0..60 {
        let jitter = if step % 2 == 0 { 0.05 } else { -0.05 };
        character.step(
            Some(GazeRequest::at(5, eye - forward * 2.0 + left * jitter)),
            dt,
        );
    }
}

#[test]
fn sweeping_all_around_respects_limits_and_speeds() {
    let mut character = Character::human();
    sweeps(&mut character);
    check_every_frame(&character);
    // Jitter straight behind does not flip the turn side.
    let last = &character.frames[character.frames.len() - 30..];
    let limits = character.chain.joints()[7].limits;
    let sides: Vec<bool> = last
        .iter()
        .map(|f| limits.swing_twist_angles(f.deltas[7]).1 > 0.0)
        .collect();
    assert!(
        sides.windows(2).all(|w| w[0] == w[1]),
        "head flips side behind"
    );
}

/// The zombie of `shared/data/bvh/zombie.bvh`: Z up, facing −Y, units of about 4 cm;
/// 3 spine joints, a neck and a head, no eyes.
fn bvh_like_chain() -> GazeChain {
    let units_per_metre = 25.0;
    let offset = |x: f32, y: f32, z: f32| Vec3::new(x, y, z) / units_per_metre;
    let up = Vec3::Z;
    let limits =
        |yaw: f32, swing: f32| JointLimits::new(up, degrees(swing), -degrees(yaw), degrees(yaw));
    let joints = [
        ChainJoint::new(
            JointRole::Spine,
            offset(0.0, 0.40032, 2.27031),
            Quat::IDENTITY,
            limits(10.0, 8.0),
        ),
        ChainJoint::new(
            JointRole::Spine,
            offset(0.0, 0.20092, 2.29656),
            Quat::IDENTITY,
            limits(10.0, 8.0),
        ),
        ChainJoint::new(
            JointRole::Spine,
            offset(0.0, 0.0, 2.30533),
            Quat::IDENTITY,
            limits(10.0, 8.0),
        ),
        ChainJoint::new(
            JointRole::Cervical,
            offset(0.0, -0.86449, 6.05149),
            Quat::IDENTITY,
            limits(35.0, 30.0),
        ),
        ChainJoint::new(
            JointRole::Head,
            offset(0.0, -0.55043, 3.12167),
            Quat::IDENTITY,
            limits(40.0, 30.0),
        ),
    ];
    let root = offset(0.0, 1.15266, 24.4236 + 1.72900);
    GazeChain::new(&joints, Vec3::NEG_Y, up, root).expect("valid chain")
}

#[test]
fn a_bvh_like_chain_without_eyes_works() {
    let chain = bvh_like_chain();
    assert!(!chain.has_eyes());
    let eye_height = chain.look_at_height(Vec3::Z);
    assert!((1.5..1.9).contains(&eye_height), "{eye_height}");
    let eye = chain.rest_eye_position();
    let dt = 1.0 / 30.0;
    // Left is up × forward = +X. Small, medium and large shifts all converge: without eyes
    // the head and neck take the eyes' band too.
    for yaw in [8.0f32, -25.0, 60.0, -90.0] {
        let mut character = Character::new(chain);
        let direction = Vec3::NEG_Y * degrees(yaw).cos() + Vec3::X * degrees(yaw).sin();
        let target = eye + direction * 3.0;
        let frame = character.run(Some(GazeRequest::at(1, target)), 5.0, dt);
        let error = frame.directions[0].angle_between((target - frame.origins[0]).normalize());
        assert!(error < degrees(0.5), "yaw {yaw}: {}°", error.to_degrees());
        let spine_moved = frame.deltas[..3].iter().any(|q| *q != Quat::IDENTITY);
        assert_eq!(spine_moved, yaw.abs() > 30.0, "yaw {yaw}");
        // Turned towards the right side.
        let (_, head_yaw) = chain.joints()[4].limits.swing_twist_angles(frame.deltas[4]);
        assert_eq!(head_yaw > 0.0, yaw > 0.0);
    }
    let mut character = Character::new(chain);
    sweeps(&mut character);
    check_every_frame(&character);
}

#[test]
fn animated_base_poses_and_moved_characters_work() {
    let mut character = Character::human();
    // An animated pose: spine leaning, neck bent, head tilted, eyes off-centre.
    let mut random = Random::new(5);
    for (index, base) in character.base.iter_mut().enumerate() {
        let axis = Vec3::new(
            random.range(-1.0, 1.0),
            random.range(-1.0, 1.0),
            random.range(-1.0, 1.0),
        )
        .normalize();
        let amount = if index < 8 { 6.0 } else { 3.0 };
        *base = Quat::from_axis_angle(axis, degrees(amount));
    }
    character.transform = CharacterTransform::from_heading(Vec3::new(4.0, 0.0, -2.0), Vec3::Y, 2.0);
    let heading = character.transform.rotation;
    let world = |yaw: f32, pitch: f32, distance: f32| {
        character.transform.position + heading * around(yaw, pitch, distance)
    };
    let dt = 1.0 / 30.0;
    for (key, target) in [
        (1, world(0.0, 0.0, 3.0)),
        (2, world(50.0, 10.0, 2.0)),
        (3, world(-100.0, -10.0, 4.0)),
    ] {
        character.run(Some(GazeRequest::at(key, target)), 5.0, dt);
        let frame = character.frames.last().unwrap();
        assert!(eye_error(frame, target) < degrees(0.5), "target {key}");
        // The reported rays agree with the public forward kinematics.
        let rays = eye_rays(
            &character.chain,
            &character.transform,
            &character.base,
            &frame.deltas,
        )
        .unwrap();
        assert!(rays.directions[0].abs_diff_eq(frame.directions[0], 1e-6));
    }
    check_every_frame(&character);
}

#[test]
fn two_targets_split_body_and_eyes() {
    let dt = 1.0 / 30.0;
    let mut character = Character::human();
    let head_target = around(60.0, 0.0, 3.0);
    let eye_target = around(75.0, 5.0, 2.0);
    let request = GazeRequest {
        style: Default::default(),
        target_key: 1,
        head_target,
        eye_target,
        interest_ratio: 1.0,
    };
    let frame = character.run(Some(request), 4.0, dt).clone();
    // The body is exactly where it would be for the head target alone.
    let mut alone = Character::human();
    let alone_frame = alone.run(Some(GazeRequest::at(1, head_target)), 4.0, dt);
    assert_eq!(frame.deltas[..8], alone_frame.deltas[..8]);
    // The eyes converge on their own target.
    assert!(eye_error(&frame, eye_target) < degrees(0.5));
}

#[test]
fn bad_frames_are_rejected_and_change_nothing() {
    let mut character = Character::human();
    character.run(
        Some(GazeRequest::at(1, around(50.0, 0.0, 2.0))),
        0.3,
        1.0 / 30.0,
    );
    let before = character.motion;
    let base = character.base.clone();
    let bad_inputs = [
        GazeInput {
            character: character.transform,
            base: &base[..9],
            request: None,
            dt: 0.03,
        },
        GazeInput {
            character: character.transform,
            base: &base,
            request: None,
            dt: -1.0,
        },
        GazeInput {
            character: character.transform,
            base: &base,
            request: None,
            dt: f32::NAN,
        },
        GazeInput {
            character: character.transform,
            base: &base,
            request: Some(GazeRequest::at(1, Vec3::NAN)),
            dt: 0.03,
        },
        GazeInput {
            character: character.transform,
            base: &base,
            request: Some(GazeRequest {
                interest_ratio: 0.0,
                ..GazeRequest::at(1, Vec3::Z)
            }),
            dt: 0.03,
        },
        GazeInput {
            character: CharacterTransform {
                position: Vec3::INFINITY,
                rotation: Quat::IDENTITY,
            },
            base: &base,
            request: None,
            dt: 0.03,
        },
    ];
    for input in bad_inputs {
        assert!(character
            .motion
            .update(
                &character.chain,
                &character.config,
                &input,
                &mut character.random
            )
            .is_err());
        assert_eq!(character.motion, before);
    }
    let other_chain = bvh_like_chain();
    let input = GazeInput {
        character: character.transform,
        base: &base[..5],
        request: None,
        dt: 0.03,
    };
    assert!(character
        .motion
        .update(
            &other_chain,
            &character.config,
            &input,
            &mut character.random
        )
        .is_err());
    assert_eq!(character.motion, before);
}

#[test]
fn a_new_target_behind_turns_the_short_way_whatever_the_last_side() {
    let dt = 1.0 / 30.0;
    for (first, behind) in [(-20.0, 160.0), (20.0, -160.0), (-100.0, 165.0)] {
        let mut character = Character::human();
        character.run(Some(GazeRequest::at(1, around(first, 0.0, 3.0))), 2.0, dt);
        let frame = character
            .run(Some(GazeRequest::at(2, around(behind, 0.0, 3.0))), 4.0, dt)
            .clone();
        let (_, head_yaw) = character.chain.joints()[7]
            .limits
            .swing_twist_angles(frame.deltas[7]);
        assert_eq!(head_yaw > 0.0, behind > 0.0, "from {first} to {behind}");
    }
}

/// A scripted character for the batch tests: chain, base pose, and what it looks at when.
struct Script {
    chain: GazeChain,
    base: Vec<Quat>,
    transform: CharacterTransform,
    seed: u64,
}

impl Script {
    fn request(&self, frame: usize) -> Option<GazeRequest> {
        let phase = (frame + 37 * self.seed as usize) % 150;
        if phase >= 120 {
            return None;
        }
        let key = (frame / 50) as u64 + self.seed;
        let yaw = (self.seed as f32 * 71.0 + key as f32 * 97.0) % 300.0 - 150.0;
        let drift = Vec3::X * (frame as f32 * 0.01);
        let up = self.chain.eye_up();
        let forward = self.chain.eye_forward();
        let direction = forward * degrees(yaw).cos() + up.cross(forward) * degrees(yaw).sin();
        let target = self.transform.position
            + self.transform.rotation * (self.chain.rest_eye_position() + direction * 2.5)
            + drift;
        Some(GazeRequest::at(key, target))
    }
}

fn scripts() -> Vec<Script> {
    let human = GazeChain::human(Vec3::Y, Vec3::Z);
    let rest: Vec<Quat> = human.joints().iter().map(|j| j.rest).collect();
    let animated: Vec<Quat> = (0..10)
        .map(|i| Quat::from_rotation_x(0.02 * i as f32) * Quat::from_rotation_y(-0.03 * i as f32))
        .collect();
    let zombie = bvh_like_chain();
    let zombie_rest: Vec<Quat> = zombie.joints().iter().map(|j| j.rest).collect();
    vec![
        Script {
            chain: human,
            base: rest.clone(),
            transform: CharacterTransform::IDENTITY,
            seed: 1,
        },
        Script {
            chain: human,
            base: animated,
            transform: CharacterTransform::from_heading(Vec3::new(2.0, 0.0, 1.0), Vec3::Y, 1.0),
            seed: 2,
        },
        Script {
            chain: zombie,
            base: zombie_rest,
            transform: CharacterTransform::IDENTITY,
            seed: 3,
        },
        Script {
            chain: human,
            base: rest,
            transform: CharacterTransform::from_heading(Vec3::new(-1.0, 0.0, 3.0), Vec3::Y, -2.5),
            seed: 4,
        },
    ]
}

type Snapshot = Vec<(Vec<Quat>, [Vec3; 2], [Vec3; 2], GazePhase)>;

/// Runs the scripts for `frames` frames, updating them in the given groups (indices into
/// the scripts); returns every character's state after every frame.
fn run_grouped(groups: &[&[usize]], frames: usize) -> Vec<Snapshot> {
    let scripts = scripts();
    let config = GazeConfig::default();
    let mut motions: Vec<GazeMotion> = scripts.iter().map(|s| GazeMotion::new(&s.chain)).collect();
    let mut randoms: Vec<Random> = (0..scripts.len())
        .map(|i| stream(9, Purpose::GazeTiming, i as u64))
        .collect();
    let mut history = Vec::new();
    for frame in 0..frames {
        let inputs: Vec<GazeInput<'_>> = scripts
            .iter()
            .map(|s| GazeInput {
                character: s.transform,
                base: &s.base,
                request: s.request(frame),
                dt: 1.0 / 30.0,
            })
            .collect();
        for group in groups {
            let mut picked_motions: Vec<&mut GazeMotion> = Vec::new();
            let mut picked_randoms: Vec<&mut Random> = Vec::new();
            for (index, (motion, random)) in motions.iter_mut().zip(randoms.iter_mut()).enumerate()
            {
                if group.contains(&index) {
                    picked_motions.push(motion);
                    picked_randoms.push(random);
                }
            }
            // Keep the group's order.
            let order: Vec<usize> = {
                let mut sorted = group.to_vec();
                sorted.sort();
                group
                    .iter()
                    .map(|i| sorted.iter().position(|j| j == i).unwrap())
                    .collect()
            };
            let mut motions_in_order: Vec<Option<&mut GazeMotion>> =
                picked_motions.into_iter().map(Some).collect();
            let mut randoms_in_order: Vec<Option<&mut Random>> =
                picked_randoms.into_iter().map(Some).collect();
            macro_rules! batch {
                ($n:literal) => {{
                    let motions: [&mut GazeMotion; $n] =
                        std::array::from_fn(|k| motions_in_order[order[k]].take().unwrap());
                    let randoms: [&mut Random; $n] =
                        std::array::from_fn(|k| randoms_in_order[order[k]].take().unwrap());
                    let chains: [&GazeChain; $n] =
                        std::array::from_fn(|k| &scripts[group[k]].chain);
                    let batch_inputs: [&GazeInput<'_>; $n] =
                        std::array::from_fn(|k| &inputs[group[k]]);
                    for result in
                        GazeMotion::update_batch(motions, chains, &config, batch_inputs, randoms)
                    {
                        result.unwrap();
                    }
                }};
            }
            match group.len() {
                1 => batch!(1),
                2 => batch!(2),
                3 => batch!(3),
                4 => batch!(4),
                _ => unreachable!(),
            }
        }
        history.push(
            motions
                .iter()
                .map(|m| {
                    (
                        m.deltas().to_vec(),
                        m.eye_origins(),
                        m.eye_directions(),
                        m.phase(),
                    )
                })
                .collect(),
        );
    }
    history
}

#[test]
fn a_character_gets_the_same_bits_whatever_its_batch() {
    let frames = 400;
    let alone = run_grouped(&[&[0], &[1], &[2], &[3]], frames);
    for groups in [
        &[&[0usize, 1, 2, 3][..]][..],
        &[&[3, 2, 1, 0][..]],
        &[&[1, 3][..], &[0, 2][..]],
        &[&[2, 0, 3][..], &[1][..]],
    ] {
        let batched = run_grouped(groups, frames);
        for frame in 0..frames {
            assert_eq!(
                batched[frame], alone[frame],
                "frame {frame}, groups {groups:?}"
            );
        }
    }
    // The scripts did exercise shifts, holds, returns and rests.
    let phases: std::collections::HashSet<_> = alone
        .iter()
        .flat_map(|f| f.iter().map(|c| format!("{:?}", c.3)))
        .collect();
    assert_eq!(phases.len(), 4, "{phases:?}");
}

#[test]
fn saccadic_shifts_land_the_eyes_in_six_frames_and_the_head_along_its_curve() {
    let mut character = Character::human();
    let dt = 1.0 / 30.0;
    // 12° to the side: an eyes-only shift.
    let target = around(12.0, 0.0, 3.0);
    let request = GazeRequest {
        style: crowdgaze::ik::MotionStyle::Saccadic,
        ..GazeRequest::at(1, target)
    };
    let mut errors = Vec::new();
    for _ in 0..8 {
        let frame = character.step(Some(request), dt);
        errors.push(degrees_of(eye_error(frame, target)));
    }
    // The shift starts at the first update (elapsed 0); six frames of 1/30 s later the
    // saccade is complete. Half-way it has not yet done half its path.
    assert!(errors[2] > 6.0, "too fast: {errors:?}");
    assert!(errors[5] < 0.5, "within 0.5° after six frames: {errors:?}");
    assert!(
        errors[6] < 0.05,
        "done at the end of the saccade: {errors:?}"
    );
    // The saccade's speed peaks in its third frame and is symmetric about it (the profile
    // 14 e^(−π/4 (x − 3)²), x = 1..6).
    let moved: Vec<f32> = errors.windows(2).map(|pair| pair[0] - pair[1]).collect();
    let peak = (0..6)
        .max_by(|&a, &b| moved[a].total_cmp(&moved[b]))
        .unwrap();
    assert_eq!(peak, 2, "speeds per frame {moved:?}");
    assert!((moved[1] - moved[3]).abs() < 0.1 && (moved[0] - moved[4]).abs() < 0.1);

    // 50° to the side: the head follows over a duration that grows with its turn.
    let mut character = Character::human();
    let far = GazeRequest {
        style: crowdgaze::ik::MotionStyle::Saccadic,
        ..GazeRequest::at(2, around(50.0, 0.0, 3.0))
    };
    character.step(Some(far), dt);
    let head_duration = character.motion.group_durations()[JointGroup::HeadAndNeck.index()];
    let timing = GazeConfig::default().timing;
    assert!(head_duration > timing.head_base_duration && head_duration < 1.5);
    assert_eq!(
        character.motion.group_durations()[JointGroup::Eyes.index()],
        timing.saccade_duration
    );
}

fn degrees_of(radians: f32) -> f32 {
    radians.to_degrees()
}
