//! The adapter's frame allocates nothing once the characters are registered: a counting
//! global allocator (counter per thread) wraps the system allocator, and a frame of 50
//! walking characters (read, viewer, step, write, interest changes) must not allocate,
//! nor must a character that stalls on a NaN transform and recovers.

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;

use crowdgaze_godot_adapter::crowdgaze::CrowdConfig;
use crowdgaze_godot_adapter::{
    CharacterSettings, PoseConvention, SceneCrowd, SkeletonAccess, Xform,
};
use glam::{Quat, Vec3};

struct CountingAllocator;

thread_local! {
    static ALLOCATIONS: Cell<u64> = const { Cell::new(0) };
}

// SAFETY: forwards every call to the system allocator unchanged; only counts.
unsafe impl GlobalAlloc for CountingAllocator {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        ALLOCATIONS.with(|count| count.set(count.get() + 1));
        // SAFETY: same contract as the caller's.
        unsafe { System.alloc(layout) }
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        // SAFETY: same contract as the caller's.
        unsafe { System.dealloc(ptr, layout) }
    }

    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        ALLOCATIONS.with(|count| count.set(count.get() + 1));
        // SAFETY: same contract as the caller's.
        unsafe { System.alloc_zeroed(layout) }
    }

    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        ALLOCATIONS.with(|count| count.set(count.get() + 1));
        // SAFETY: same contract as the caller's.
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

#[global_allocator]
static GLOBAL: CountingAllocator = CountingAllocator;

/// Number of allocations `work` made on this thread.
fn allocations_during<R>(work: impl FnOnce() -> R) -> (u64, R) {
    let before = ALLOCATIONS.with(Cell::get);
    let result = work();
    (ALLOCATIONS.with(Cell::get) - before, result)
}

/// A humanoid skeleton whose poses are plain data, posed as Godot 3's.
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

fn human(place: Vec3) -> Skeleton {
    let bones: [(&str, Option<usize>, [f32; 3]); 9] = [
        ("Hips", None, [0.0, 0.95, 0.0]),
        ("Spine", Some(0), [0.0, 0.1, 0.0]),
        ("Spine1", Some(1), [0.0, 0.2, 0.0]),
        ("Spine2", Some(2), [0.0, 0.2, 0.0]),
        ("Neck", Some(3), [0.0, 0.12, 0.0]),
        ("Head", Some(4), [0.0, 0.08, 0.0]),
        ("LeftEye", Some(5), [0.03, 0.07, 0.09]),
        ("RightEye", Some(5), [-0.03, 0.07, 0.09]),
        ("LeftUpLeg", Some(0), [0.1, -0.05, 0.0]),
    ];
    Skeleton {
        names: bones.iter().map(|b| b.0.to_string()).collect(),
        parents: bones.iter().map(|b| b.1).collect(),
        rests: bones
            .iter()
            .map(|b| Xform::from_rotation_translation(Quat::IDENTITY, Vec3::from_array(b.2)))
            .collect(),
        poses: vec![Xform::IDENTITY; bones.len()],
        global: Xform::from_rotation_translation(Quat::IDENTITY, place),
    }
}

#[test]
fn a_frame_allocates_nothing() {
    let mut scene: SceneCrowd<usize> =
        SceneCrowd::new(CrowdConfig::default(), PoseConvention::RestTimesPose).unwrap();
    let mut skeletons: Vec<Skeleton> = (0..50)
        .map(|k| human(Vec3::new((k % 7) as f32 * 2.0, 0.0, (k / 7) as f32 * 2.0)))
        .collect();
    for (k, skeleton) in skeletons.iter().enumerate() {
        scene
            .add_character(
                k as i64,
                k,
                skeleton,
                &Xform::IDENTITY,
                &CharacterSettings::default(),
            )
            .unwrap();
    }
    scene
        .add_target(100, 100, &Xform::IDENTITY, 1.5, 2.0)
        .unwrap();
    let mut changes = 0;
    let frame = |skeletons: &mut Vec<Skeleton>, scene: &mut SceneCrowd<usize>, n: usize| {
        for (k, skeleton) in skeletons.iter_mut().enumerate() {
            let angle = n as f32 / 30.0 + k as f32;
            let place = skeleton.global.origin;
            skeleton.global = Xform::from_rotation_translation(
                Quat::from_rotation_y(angle),
                place + Vec3::new(angle.cos(), 0.0, angle.sin()) * 0.02,
            );
            skeleton.poses[1] = Xform::from_rotation_translation(
                Quat::from_rotation_y(0.1 * angle.sin()),
                Vec3::ZERO,
            );
        }
        // A stall and a recovery on the way.
        let spoiled = n % 40 == 20;
        if spoiled {
            skeletons[3].poses[2].origin.x = f32::NAN;
        } else {
            skeletons[3].poses[2].origin.x = 0.0;
        }
        for (slot, skeleton) in skeletons.iter().enumerate() {
            let result = scene.read_character(slot, skeleton, &Xform::IDENTITY);
            assert_eq!(result.is_err(), spoiled && slot == 3);
        }
        scene.read_target(0, &Xform::IDENTITY).unwrap();
        scene
            .set_viewer(Some(Vec3::new(n as f32 * 0.05, 1.7, 4.0)), 3.0)
            .unwrap();
        scene.step(1.0 / 30.0).unwrap();
        for (slot, skeleton) in skeletons.iter_mut().enumerate() {
            scene.write_character(slot, skeleton).unwrap();
        }
        scene.interest_changes().len()
    };
    // Warm-up: the first frames may allocate (the error message of the first stall does).
    for n in 0..60 {
        changes += frame(&mut skeletons, &mut scene, n);
    }
    for n in 60..200 {
        // The stall's error carries a message (an allocation), reported once per stall.
        if n % 40 == 20 {
            changes += frame(&mut skeletons, &mut scene, n);
            continue;
        }
        let (count, changed) = allocations_during(|| frame(&mut skeletons, &mut scene, n));
        assert_eq!(count, 0, "frame {n} allocated {count} times");
        changes += changed;
    }
    assert!(
        changes > 0,
        "nobody ever changed interest: the frame did nothing"
    );
}
