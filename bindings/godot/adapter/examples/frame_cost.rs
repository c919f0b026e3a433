//! What one frame of the adapter costs without an engine: `n` characters (default 1000) on
//! a 2.5 m grid, each walking a circle, with skeletons that pose themselves as Godot 3's.
//! Prints the medians of the read, step and write phases over 300 frames. A profiling
//! harness, not a test: `cargo run --release -p crowdgaze-godot-adapter --example
//! frame_cost -- 1000`.

use std::time::Instant;

use crowdgaze::CrowdConfig;
use crowdgaze_godot_adapter::{
    CharacterSettings, PoseConvention, SceneCrowd, SkeletonAccess, Xform,
};
use glam::{Quat, Vec3};

/// A humanoid skeleton whose poses are plain data.
#[derive(Clone)]
struct Skeleton {
    names: Vec<String>,
    parents: Vec<Option<usize>>,
    rests: Vec<Xform>,
    poses: Vec<Xform>,
    global: Xform,
}

impl SkeletonAccess for Skeleton {
    fn bone_count(&self) -> usize {
        self.names.len()
    }
    fn bone_name(&self, bone: usize) -> String {
        self.names[bone].clone()
    }
    fn bone_parent(&self, bone: usize) -> Option<usize> {
        self.parents[bone]
    }
    fn bone_rest(&self, bone: usize) -> Xform {
        self.rests[bone]
    }
    fn bone_pose(&self, bone: usize) -> Xform {
        self.poses[bone]
    }
    fn set_bone_pose(&mut self, bone: usize, pose: Xform) {
        self.poses[bone] = pose;
    }
    fn global_transform(&self) -> Xform {
        self.global
    }
}

fn human() -> Skeleton {
    let bones: [(&str, Option<usize>, [f32; 3]); 10] = [
        ("Hips", None, [0.0, 0.95, 0.0]),
        ("Spine", Some(0), [0.0, 0.1, 0.0]),
        ("Spine1", Some(1), [0.0, 0.12, 0.0]),
        ("Spine2", Some(2), [0.0, 0.12, 0.0]),
        ("Spine3", Some(3), [0.0, 0.12, 0.0]),
        ("Neck", Some(4), [0.0, 0.12, 0.0]),
        ("Head", Some(5), [0.0, 0.08, 0.0]),
        ("LeftEye", Some(6), [0.03, 0.07, 0.09]),
        ("RightEye", Some(6), [-0.03, 0.07, 0.09]),
        ("LeftUpLeg", Some(0), [0.1, -0.05, 0.0]),
    ];
    let rests: Vec<Xform> = bones
        .iter()
        .map(|b| Xform::from_rotation_translation(Quat::IDENTITY, Vec3::from_array(b.2)))
        .collect();
    Skeleton {
        names: bones.iter().map(|b| b.0.to_string()).collect(),
        parents: bones.iter().map(|b| b.1).collect(),
        poses: vec![Xform::IDENTITY; rests.len()],
        rests,
        global: Xform::IDENTITY,
    }
}

fn median(mut values: Vec<f64>) -> f64 {
    values.sort_by(f64::total_cmp);
    values[values.len() / 2]
}

fn main() {
    let count: usize = std::env::args()
        .nth(1)
        .and_then(|a| a.parse().ok())
        .unwrap_or(1000);
    let config = CrowdConfig {
        max_characters: count as u32 + 1,
        ..CrowdConfig::default()
    };
    let mut scene: SceneCrowd<usize> =
        SceneCrowd::new(config, PoseConvention::RestTimesPose).expect("crowd");
    let side = (count as f32).sqrt().ceil() as usize;
    let mut skeletons = Vec::new();
    let mut centres = Vec::new();
    for k in 0..count {
        let centre = Vec3::new((k % side) as f32 * 2.5, 0.0, (k / side) as f32 * 2.5);
        let mut skeleton = human();
        skeleton.global = Xform::from_rotation_translation(Quat::IDENTITY, centre);
        scene
            .add_character(
                k as i64,
                k,
                &skeleton,
                &Xform::IDENTITY,
                &CharacterSettings::default(),
            )
            .expect("character");
        skeletons.push(skeleton);
        centres.push(centre);
    }
    let (mut read, mut step, mut write) = (Vec::new(), Vec::new(), Vec::new());
    for frame in 0..330 {
        for (k, skeleton) in skeletons.iter_mut().enumerate() {
            let angle = frame as f32 / 30.0 * 0.8 + k as f32;
            let heading = (-angle.sin()).atan2(angle.cos());
            skeleton.global = Xform::from_rotation_translation(
                Quat::from_rotation_y(heading),
                centres[k] + Vec3::new(angle.cos(), 0.0, angle.sin()) * 0.8,
            );
            skeleton.poses[1] = Xform::from_rotation_translation(
                Quat::from_rotation_y(0.05 * (angle * 3.0).sin()),
                Vec3::ZERO,
            );
        }
        let start = Instant::now();
        for (slot, skeleton) in skeletons.iter().enumerate() {
            scene
                .read_character(slot, skeleton, &Xform::IDENTITY)
                .expect("read");
        }
        let read_done = start.elapsed();
        scene.step(1.0 / 30.0).expect("step");
        let step_done = start.elapsed();
        for (slot, skeleton) in skeletons.iter_mut().enumerate() {
            scene.write_character(slot, skeleton).expect("write");
        }
        let write_done = start.elapsed();
        if frame >= 30 {
            read.push(read_done.as_secs_f64() * 1e3);
            step.push((step_done - read_done).as_secs_f64() * 1e3);
            write.push((write_done - step_done).as_secs_f64() * 1e3);
        }
    }
    println!(
        "{count} characters: read {:.3} ms, step {:.3} ms, write {:.3} ms (medians of 300 frames)",
        median(read),
        median(step),
        median(write)
    );
}
