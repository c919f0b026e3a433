//! The adapter against skeletons that compute their poses as Godot 3 and Godot 4 do: the
//! gaze read back from the skeleton's own global poses, in its world.

use crowdgaze::crowd::{ExplicitTarget, TargetPriority};
use crowdgaze::scene::ids::NO_ENTITY;
use crowdgaze::skeleton_map::{BoneMap, BoneRole};
use crowdgaze::{CrowdConfig, Error};
use glam::{EulerRot, Mat3, Quat, Vec3};

use crate::crowd::{CharacterSettings, EntityNode, InterestChange, SceneCrowd};
use crate::skeleton::{PoseConvention, SkeletonAccess};
use crate::xform::{rotation_of, Xform};

/// A skeleton that poses itself as Godot does.
#[derive(Debug, Clone)]
pub(crate) struct FakeSkeleton {
    pub(crate) names: Vec<String>,
    pub(crate) parents: Vec<Option<usize>>,
    rests: Vec<Xform>,
    poses: Vec<Xform>,
    pub(crate) global: Xform,
    convention: PoseConvention,
    /// How many poses were written.
    writes: usize,
}

impl SkeletonAccess for FakeSkeleton {
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
        self.writes += 1;
    }
    fn global_transform(&self) -> Xform {
        self.global
    }
}

/// Bone positions of a standing human (Y up, facing +Z), parent indices.
const HUMAN: &[(&str, Option<usize>, [f32; 3])] = &[
    ("Hips", None, [0.0, 0.95, 0.0]),
    ("Spine", Some(0), [0.0, 1.05, 0.0]),
    ("Chest", Some(1), [0.0, 1.30, 0.02]),
    ("Neck", Some(2), [0.0, 1.50, 0.0]),
    ("Head", Some(3), [0.0, 1.58, 0.0]),
    ("LeftEye", Some(4), [0.032, 1.64, 0.085]),
    ("RightEye", Some(4), [-0.032, 1.64, 0.085]),
    ("LeftUpLeg", Some(0), [0.1, 0.9, 0.0]),
    ("RightUpLeg", Some(0), [-0.1, 0.9, 0.0]),
];

impl FakeSkeleton {
    /// The human, its rests rotated as importers do (a different turn per bone), `unit`
    /// skeleton units per metre, placed at `global`.
    pub(crate) fn human(convention: PoseConvention, global: Xform, unit: f32) -> FakeSkeleton {
        let turns: Vec<Quat> = (0..HUMAN.len())
            .map(|i| Quat::from_euler(EulerRot::YXZ, 0.4 * i as f32, 0.3, -0.2 + 0.1 * i as f32))
            .collect();
        let mut skeleton = FakeSkeleton::empty(convention, global);
        for (i, (name, parent, position)) in HUMAN.iter().enumerate() {
            let world = Vec3::from_array(*position) * unit;
            let (parent_turn, parent_world) = match parent {
                None => (Quat::IDENTITY, Vec3::ZERO),
                Some(p) => (turns[*p], Vec3::from_array(HUMAN[*p].2) * unit),
            };
            let rest = Xform::from_rotation_translation(
                parent_turn.conjugate() * turns[i],
                parent_turn.conjugate() * (world - parent_world),
            );
            skeleton.push(name, *parent, rest);
        }
        skeleton
    }

    /// No bone yet, placed at `global`.
    fn empty(convention: PoseConvention, global: Xform) -> FakeSkeleton {
        FakeSkeleton {
            names: Vec::new(),
            parents: Vec::new(),
            rests: Vec::new(),
            poses: Vec::new(),
            global,
            convention,
            writes: 0,
        }
    }

    /// Adds a bone at rest.
    fn push(&mut self, name: &str, parent: Option<usize>, rest: Xform) {
        self.names.push(name.to_string());
        self.parents.push(parent);
        self.rests.push(rest);
        self.poses.push(match self.convention {
            PoseConvention::RestTimesPose => Xform::IDENTITY,
            PoseConvention::PoseIsLocal => rest,
        });
    }

    fn local(&self, bone: usize) -> Xform {
        match self.convention {
            PoseConvention::RestTimesPose => self.rests[bone].mul(&self.poses[bone]),
            PoseConvention::PoseIsLocal => self.poses[bone],
        }
    }

    /// A bone's pose in the skeleton's frame, as Godot's `get_bone_global_pose`.
    fn bone_global_pose(&self, bone: usize) -> Xform {
        match self.parents[bone] {
            Some(parent) => self.bone_global_pose(parent).mul(&self.local(bone)),
            None => self.local(bone),
        }
    }

    /// A bone's transform in the world.
    fn world_pose(&self, bone: usize) -> Xform {
        self.global.mul(&self.bone_global_pose(bone))
    }

    /// The rest pose of a bone in the skeleton's frame.
    fn rest_global(&self, bone: usize) -> Xform {
        match self.parents[bone] {
            Some(parent) => self.rest_global(parent).mul(&self.rests[bone]),
            None => self.rests[bone],
        }
    }

    /// An eye's forward axis in its own frame: the skeleton's +Z at rest.
    fn eye_local_forward(&self, bone: usize) -> Vec3 {
        rotation_of(&self.rest_global(bone).basis).conjugate() * Vec3::Z
    }

    fn bone(&self, name: &str) -> usize {
        self.names.iter().position(|n| n == name).unwrap()
    }

    /// Sets a bone's local rotation to `rest rotation * turn`, in either convention.
    fn animate(&mut self, bone: usize, turn: Quat) {
        let rest = self.rests[bone];
        self.poses[bone] = match self.convention {
            PoseConvention::RestTimesPose => Xform::from_rotation_translation(turn, Vec3::ZERO),
            PoseConvention::PoseIsLocal => Xform {
                basis: rest.basis * Mat3::from_quat(turn),
                origin: rest.origin,
            },
        };
    }
}

/// A placement: `heading` about +Y at `position`.
fn placed(position: Vec3, heading: f32) -> Xform {
    Xform::from_rotation_translation(Quat::from_rotation_y(heading), position)
}

/// The angle between two rotations (precise near 0, unlike an arc cosine).
fn angle(a: Quat, b: Quat) -> f32 {
    let between = a.conjugate() * b;
    2.0 * between.xyz().length().atan2(between.w.abs())
}

struct World {
    crowd: SceneCrowd<u32>,
    skeletons: Vec<FakeSkeleton>,
    nodes: Vec<Xform>,
}

impl World {
    fn new(config: CrowdConfig, convention: PoseConvention) -> World {
        World {
            crowd: SceneCrowd::new(config, convention).unwrap(),
            skeletons: Vec::new(),
            nodes: Vec::new(),
        }
    }

    /// Adds a character whose node is its skeleton's child at identity.
    fn add(&mut self, skeleton: FakeSkeleton) -> crowdgaze::Result<u32> {
        self.add_with(skeleton, &CharacterSettings::default())
    }

    /// Adds a character with `settings`, its node its skeleton's child at identity (key
    /// 1000 + its index).
    fn add_with(
        &mut self,
        skeleton: FakeSkeleton,
        settings: &CharacterSettings,
    ) -> crowdgaze::Result<u32> {
        let key = 1000 + self.skeletons.len() as i64;
        let node = Xform::IDENTITY;
        let id = self.crowd.add_character(
            key,
            self.skeletons.len() as u32,
            &skeleton,
            &node,
            settings,
        )?;
        self.skeletons.push(skeleton);
        self.nodes.push(node);
        Ok(id)
    }

    /// One frame: read every character, step, write.
    fn frame(&mut self, dt: f32) {
        for slot in 0..self.crowd.character_count() {
            let index = *self.crowd.character_handle(slot).unwrap() as usize;
            let _ = self
                .crowd
                .read_character(slot, &self.skeletons[index], &self.nodes[index]);
        }
        self.crowd.step(dt).unwrap();
        for slot in 0..self.crowd.character_count() {
            let index = *self.crowd.character_handle(slot).unwrap() as usize;
            self.crowd
                .write_character(slot, &mut self.skeletons[index])
                .unwrap();
        }
    }
}

/// The local rotations of `bones` read back from `skeleton`'s global poses (the first in
/// the character frame of the node at `node` under the skeleton), as the library gives them.
fn skeleton_locals(skeleton: &FakeSkeleton, node: &Xform, bones: &[usize]) -> Vec<Quat> {
    let (_, _, frame) = crate::skeleton::character_frame(&skeleton.global.mul(node));
    bones
        .iter()
        .enumerate()
        .map(|(k, &bone)| {
            let parent = match skeleton.parents[bone] {
                Some(p) if k > 0 => skeleton.world_pose(p),
                _ => frame,
            };
            rotation_of(
                &parent
                    .inverse()
                    .unwrap()
                    .mul(&skeleton.world_pose(bone))
                    .basis,
            )
        })
        .collect()
}

/// The largest difference between the library's rotations and the local rotations read
/// back from the skeleton's global poses (the first in the character frame), radians.
fn pose_error(world: &World, slot: usize) -> f32 {
    let index = *world.crowd.character_handle(slot).unwrap() as usize;
    let skeleton = &world.skeletons[index];
    let bones = world.crowd.chain_bones(slot).unwrap().to_vec();
    let mut library = [Quat::IDENTITY; 15];
    let count = world.crowd.joint_rotations(slot, &mut library).unwrap();
    assert_eq!(count, bones.len());
    skeleton_locals(skeleton, &world.nodes[index], &bones)
        .iter()
        .zip(library)
        .map(|(&local, gaze)| angle(local, gaze))
        .fold(0.0, f32::max)
}

/// The angle between each eye's forward and the direction to `point`, radians (largest).
fn eye_error(skeleton: &FakeSkeleton, point: Vec3) -> f32 {
    eyes_error(skeleton, ["LeftEye", "RightEye"], point)
}

/// [`eye_error`] for eyes of other names.
fn eyes_error(skeleton: &FakeSkeleton, eyes: [&str; 2], point: Vec3) -> f32 {
    eyes.iter()
        .map(|name| {
            let eye = skeleton.bone(name);
            let pose = skeleton.world_pose(eye);
            let forward = (pose.basis * skeleton.eye_local_forward(eye)).normalize();
            forward.angle_between(point - pose.origin)
        })
        .fold(0.0, f32::max)
}

#[test]
fn the_eyes_look_at_the_target_in_the_skeletons_world() {
    for convention in [PoseConvention::RestTimesPose, PoseConvention::PoseIsLocal] {
        let mut world = World::new(CrowdConfig::default(), convention);
        let place = placed(Vec3::new(1.0, 0.0, 2.0), 0.5);
        let id = world
            .add(FakeSkeleton::human(convention, place, 1.0))
            .unwrap();
        let lamp = place.transform_point(Vec3::new(1.2, 0.0, 2.5));
        let target = world
            .crowd
            .add_target(
                7,
                99,
                &Xform::from_rotation_translation(Quat::IDENTITY, lamp),
                2.2,
                1.0,
            )
            .unwrap();
        world
            .crowd
            .crowd_mut()
            .set_gaze_target(id, ExplicitTarget::Entity(target), TargetPriority::Override)
            .unwrap();
        let point = lamp + Vec3::Y * 2.2;
        let mut held = 0;
        for _ in 0..120 {
            world.frame(1.0 / 30.0);
            assert!(pose_error(&world, 0) < 1e-5, "{convention:?}");
            if world.crowd.is_holding(0).unwrap() {
                held += 1;
                let error = eye_error(&world.skeletons[0], point).to_degrees();
                assert!(error < 0.5, "{convention:?}: the eyes are {error}° off");
            }
        }
        assert!(held > 30, "{convention:?}: held for {held} frames");
        let gaze = world.crowd.gaze(0).unwrap();
        assert_eq!(gaze.target, target);
        assert!(gaze.target_position.abs_diff_eq(point, 1e-4));
        assert!(matches!(
            world.crowd.node_of(target),
            EntityNode::Target(&99)
        ));
    }
}

#[test]
fn the_animation_is_the_base_and_the_gaze_never_feeds_back() {
    for convention in [PoseConvention::RestTimesPose, PoseConvention::PoseIsLocal] {
        // Three crowds of one, each looking at the same point: one whose animation sets
        // the rest pose every frame, one nobody animates, one with a swaying spine.
        let place = placed(Vec3::new(1.0, 0.0, -1.0), 0.3);
        let point = place.transform_point(Vec3::new(-2.0, 1.0, 3.0));
        let mut worlds: Vec<World> = (0..3)
            .map(|_| {
                let mut world = World::new(CrowdConfig::default(), convention);
                let id = world
                    .add(FakeSkeleton::human(convention, place, 1.0))
                    .unwrap();
                world
                    .crowd
                    .crowd_mut()
                    .set_gaze_target(id, ExplicitTarget::Point(point), TargetPriority::Override)
                    .unwrap();
                world
            })
            .collect();
        let rest = worlds[0].skeletons[0].clone();
        let spine = rest.bone("Spine");
        for frame in 0..90 {
            worlds[0].skeletons[0].poses = rest.poses.clone();
            let sway = Quat::from_rotation_z(0.1 * (frame as f32 * 0.2).sin());
            worlds[2].skeletons[0].animate(spine, sway);
            for world in &mut worlds {
                world.frame(1.0 / 30.0);
            }
            let mut a = [Quat::IDENTITY; 15];
            let mut b = [Quat::IDENTITY; 15];
            worlds[0].crowd.joint_rotations(0, &mut a).unwrap();
            worlds[1].crowd.joint_rotations(0, &mut b).unwrap();
            assert_eq!(
                a, b,
                "{convention:?} frame {frame}: the written gaze fed back"
            );
            // The swaying spine is the base under the gaze: final = (root · rest · sway) · delta.
            let mut c = [Quat::IDENTITY; 15];
            worlds[2].crowd.joint_rotations(0, &mut c).unwrap();
            let id = worlds[2].crowd.entity_of(1000).unwrap();
            let delta = worlds[2].crowd.crowd().gaze_motion(id).unwrap().deltas()[0];
            let (rest_spine, rest_hips) = (
                rotation_of(&rest.rests[spine].basis),
                rotation_of(&rest.rests[0].basis),
            );
            let expected = Quat::from_rotation_y(0.3).conjugate()
                * rotation_of(&place.basis)
                * rest_hips
                * rest_spine
                * sway
                * delta;
            assert!(angle(c[0], expected) < 1e-5, "{convention:?} frame {frame}");
            assert!(pose_error(&worlds[2], 0) < 1e-5);
        }
        for world in &worlds {
            assert!(eye_error(&world.skeletons[0], point).to_degrees() < 1.0);
        }
    }
}

#[test]
fn a_skeleton_without_a_head_is_refused_with_its_bones_named() {
    let mut world = World::new(CrowdConfig::default(), PoseConvention::RestTimesPose);
    let mut skeleton = FakeSkeleton::human(PoseConvention::RestTimesPose, Xform::IDENTITY, 1.0);
    skeleton.names[4] = "Skull".into();
    let error = world.add(skeleton.clone()).unwrap_err();
    let text = error.to_string();
    assert!(matches!(error, Error::InvalidArgument(_)));
    assert!(
        text.contains("no head bone") && text.contains("'Hips', 'Spine', 'Chest', 'Neck', 'Skull'"),
        "{text}"
    );
    assert_eq!(world.crowd.character_count(), 0);
    assert_eq!(world.crowd.crowd().character_count(), 0);
    world.frame(1.0 / 30.0);
    // Mapped by an override, the same skeleton is taken.
    let mut map = BoneMap::default();
    map.set("Skull", BoneRole::Head);
    let settings = CharacterSettings {
        bone_map: map,
        impact: 2.0,
        ..CharacterSettings::default()
    };
    let id = world
        .crowd
        .add_character(5, 0, &skeleton, &Xform::IDENTITY, &settings)
        .unwrap();
    assert_eq!(world.crowd.entity_of(5), Some(id));
    assert_eq!(world.crowd.chain_bones(0).unwrap(), &[1, 2, 3, 4, 5, 6]);
    assert!((world.crowd.look_at_height(0).unwrap() - 1.64).abs() < 1e-4);
    assert!(world
        .crowd
        .add_character(5, 0, &skeleton, &Xform::IDENTITY, &settings)
        .is_err());
}

#[test]
fn non_finite_transforms_stall_the_character_and_are_reported_once() {
    let mut world = World::new(CrowdConfig::default(), PoseConvention::RestTimesPose);
    world
        .add(FakeSkeleton::human(
            PoseConvention::RestTimesPose,
            placed(Vec3::ZERO, 0.0),
            1.0,
        ))
        .unwrap();
    world
        .add(FakeSkeleton::human(
            PoseConvention::RestTimesPose,
            placed(Vec3::new(0.0, 0.0, 3.0), 3.1),
            1.0,
        ))
        .unwrap();
    for _ in 0..30 {
        world.frame(1.0 / 30.0);
    }
    let before = world.skeletons[0].poses.clone();
    let writes = world.skeletons[0].writes;
    let position = world.crowd.crowd().scene().positions()[0];
    type Spoil = Box<dyn Fn(&mut World)>;
    let bad_cases: [Spoil; 3] = [
        Box::new(|w| w.nodes[0].origin.x = f32::NAN),
        Box::new(|w| w.skeletons[0].global.basis.x_axis.y = f32::INFINITY),
        Box::new(|w| w.skeletons[0].poses[3].basis.y_axis.z = f32::NAN),
    ];
    for spoil in bad_cases {
        let good = (world.nodes[0], world.skeletons[0].clone());
        spoil(&mut world);
        let first = world
            .crowd
            .read_character(0, &world.skeletons[0], &world.nodes[0]);
        assert!(matches!(first, Err(Error::NonFinite(_))), "{first:?}");
        world.crowd.step(1.0 / 30.0).unwrap();
        world
            .crowd
            .write_character(0, &mut world.skeletons[0])
            .unwrap();
        // Reported once: the next frames are quiet, and nothing moves or is written.
        for _ in 0..5 {
            assert!(world
                .crowd
                .read_character(0, &world.skeletons[0], &world.nodes[0])
                .is_ok());
            world.crowd.step(1.0 / 30.0).unwrap();
            world
                .crowd
                .write_character(0, &mut world.skeletons[0])
                .unwrap();
        }
        assert_eq!(world.crowd.crowd().scene().positions()[0], position);
        assert_eq!(world.skeletons[0].writes, writes);
        for rotation in world.crowd.crowd().gaze_motion(0).unwrap().deltas() {
            assert!(rotation.is_finite());
        }
        (world.nodes[0], world.skeletons[0]) = good;
        world.skeletons[0].poses = before.clone();
        world.frame(1.0 / 30.0);
        world.skeletons[0].writes = writes;
        assert!(pose_error(&world, 0) < 1e-5);
    }
    // A skeleton that lost bones is mapped again (a new entity).
    let before = world.crowd.entity_of(1001).unwrap();
    world.skeletons[1].names.pop();
    world
        .crowd
        .read_character(1, &world.skeletons[1], &world.nodes[1])
        .unwrap();
    assert_ne!(world.crowd.entity_of(1001).unwrap(), before);
}

#[test]
fn removed_nodes_leave_the_crowd_at_once() {
    let mut world = World::new(CrowdConfig::default(), PoseConvention::PoseIsLocal);
    let ids: Vec<u32> = (0..3)
        .map(|k| {
            world
                .add(FakeSkeleton::human(
                    PoseConvention::PoseIsLocal,
                    placed(Vec3::new(k as f32, 0.0, 0.0), 0.0),
                    1.0,
                ))
                .unwrap()
        })
        .collect();
    let target = world
        .crowd
        .add_target(50, 50, &placed(Vec3::new(0.0, 0.0, 3.0), 0.0), 1.0, 1.0)
        .unwrap();
    world
        .crowd
        .crowd_mut()
        .set_gaze_target(
            ids[2],
            ExplicitTarget::Entity(target),
            TargetPriority::Override,
        )
        .unwrap();
    world.frame(1.0 / 30.0);
    assert_eq!(
        world.crowd.interest_changes(),
        &[InterestChange {
            slot: 2,
            from: NO_ENTITY,
            to: target
        }]
    );
    assert_eq!(world.crowd.remove(1000), Some(0));
    assert_eq!(world.crowd.crowd().character_count(), 2);
    assert!(matches!(world.crowd.node_of(ids[0]), EntityNode::None));
    // The last character moved into slot 0 and is still itself.
    assert_eq!(world.crowd.character_slot(1002), Some(0));
    assert!(matches!(
        world.crowd.node_of(ids[2]),
        EntityNode::Character(&2)
    ));
    assert_eq!(world.crowd.gaze(0).unwrap().character, ids[2]);
    world.frame(1.0 / 30.0);
    assert!(pose_error(&world, 0) < 1e-5);
    // Its target leaves: it looks elsewhere, and says so.
    assert_eq!(world.crowd.remove(50), Some(50));
    assert_eq!(world.crowd.remove(50), None);
    world.frame(1.0 / 30.0);
    assert_eq!(world.crowd.gaze(0).unwrap().target, NO_ENTITY);
    assert!(
        world
            .crowd
            .interest_changes()
            .iter()
            .any(|change| change.slot == 0 && change.to == NO_ENTITY)
            || world.crowd.interest_changes().is_empty()
    );
    assert_eq!(world.crowd.remove(1001), Some(1));
    assert_eq!(world.crowd.remove(1002), Some(2));
    assert_eq!(world.crowd.character_count(), 0);
    world.frame(1.0 / 30.0);
}

#[test]
fn an_empty_scene_and_a_lone_viewer_step() {
    let mut world = World::new(CrowdConfig::default(), PoseConvention::RestTimesPose);
    for frame in 0..10 {
        world.frame(1.0 / 30.0);
        world
            .crowd
            .set_viewer(Some(Vec3::new(frame as f32, 1.7, 0.0)), 3.0)
            .unwrap();
    }
    let viewer = world.crowd.viewer().unwrap();
    assert!(matches!(world.crowd.node_of(viewer), EntityNode::Viewer));
    assert!(world.crowd.set_viewer(Some(Vec3::NAN), 1.0).is_err());
    world.crowd.set_viewer(None, 1.0).unwrap();
    world.frame(1.0 / 30.0);
    assert!(world.crowd.viewer().is_none());
    assert!(world.crowd.step(f32::NAN).is_err());
    // Godot 3's negative deltas are no time passing.
    assert!(world.crowd.step(-1.0).is_ok());
    world.frame(0.0);
}

#[test]
fn characters_notice_the_viewer_walking_past() {
    let mut world = World::new(CrowdConfig::default(), PoseConvention::RestTimesPose);
    for k in 0..4 {
        world
            .add(FakeSkeleton::human(
                PoseConvention::RestTimesPose,
                placed(Vec3::new(2.0 * k as f32, 0.0, 0.0), 0.0),
                1.0,
            ))
            .unwrap();
    }
    let mut seen = 0;
    for frame in 0..600 {
        let x = -5.0 + 20.0 * frame as f32 / 600.0;
        world
            .crowd
            .set_viewer(Some(Vec3::new(x, 1.7, 3.0)), 5.0)
            .unwrap();
        world.frame(1.0 / 30.0);
        let viewer = world.crowd.viewer().unwrap();
        seen += world
            .crowd
            .interest_changes()
            .iter()
            .filter(|change| change.to == viewer)
            .count();
    }
    assert!(seen > 0, "nobody looked at the viewer");
}

#[test]
fn capacities_and_scales() {
    let config = CrowdConfig {
        max_characters: 1,
        ..CrowdConfig::default()
    };
    let mut world = World::new(config, PoseConvention::RestTimesPose);
    // A skeleton in centimetres under a node scaled by 0.01: the chain is in metres.
    let mut global = placed(Vec3::new(3.0, 0.0, 0.0), 1.0);
    global.basis *= 0.01;
    let id = world
        .add(FakeSkeleton::human(
            PoseConvention::RestTimesPose,
            global,
            100.0,
        ))
        .unwrap();
    let chain = *world.crowd.crowd().chain(id).unwrap();
    assert!((chain.look_at_height(Vec3::Y) - 1.64).abs() < 1e-4);
    assert!((chain.root_offset() - Vec3::new(0.0, 0.95, 0.0)).length() < 1e-4);
    let refused = world.add(FakeSkeleton::human(
        PoseConvention::RestTimesPose,
        Xform::IDENTITY,
        1.0,
    ));
    assert!(matches!(refused, Err(Error::Capacity(_))));
    world
        .crowd
        .crowd_mut()
        .set_gaze_target(
            id,
            ExplicitTarget::Point(Vec3::new(4.0, 1.0, 2.0)),
            TargetPriority::Override,
        )
        .unwrap();
    for _ in 0..60 {
        world.frame(1.0 / 30.0);
        assert!(pose_error(&world, 0) < 1e-5);
    }
    assert!(eye_error(&world.skeletons[0], Vec3::new(4.0, 1.0, 2.0)).to_degrees() < 1.0);
    let wrong_world = CrowdConfig {
        world: crowdgaze::World::new(crowdgaze::Axis::PositiveZ, crowdgaze::Axis::PositiveX, 1.0)
            .unwrap(),
        ..CrowdConfig::default()
    };
    assert!(SceneCrowd::<u32>::new(wrong_world, PoseConvention::PoseIsLocal).is_err());
}

#[test]
fn scaled_bone_poses_keep_their_scale_and_translation() {
    for convention in [PoseConvention::RestTimesPose, PoseConvention::PoseIsLocal] {
        let mut world = World::new(CrowdConfig::default(), convention);
        let id = world
            .add(FakeSkeleton::human(
                convention,
                placed(Vec3::ZERO, 0.0),
                1.0,
            ))
            .unwrap();
        let neck = world.skeletons[0].bone("Neck");
        let turn = Quat::from_rotation_x(0.2);
        world.skeletons[0].animate(neck, turn);
        let scale = Vec3::new(1.1, 0.9, 1.2);
        world.skeletons[0].poses[neck].basis *= glam::Mat3::from_diagonal(scale);
        let origin = world.skeletons[0].poses[neck].origin + Vec3::new(0.0, 0.01, 0.0);
        world.skeletons[0].poses[neck].origin = origin;
        world
            .crowd
            .crowd_mut()
            .set_gaze_target(
                id,
                ExplicitTarget::Point(Vec3::new(2.0, 1.5, 2.0)),
                TargetPriority::Override,
            )
            .unwrap();
        for _ in 0..30 {
            world.frame(1.0 / 30.0);
        }
        let pose = world.skeletons[0].poses[neck];
        assert!(pose.scale().abs_diff_eq(scale, 1e-5), "{convention:?}");
        assert_eq!(pose.origin, origin);
        // The base the library used is the animated rotation, scale removed.
        let slot_bones = world.crowd.chain_bones(0).unwrap().to_vec();
        let k = slot_bones.iter().position(|&b| b == neck).unwrap();
        let delta = world.crowd.crowd().gaze_motion(id).unwrap().deltas()[k];
        let mut rotations = [Quat::IDENTITY; 15];
        world.crowd.joint_rotations(0, &mut rotations).unwrap();
        let rest = rotation_of(&world.skeletons[0].rests[neck].basis);
        assert!(
            angle(rotations[k], rest * turn * delta) < 1e-5,
            "{convention:?}"
        );
    }
}

#[test]
fn mirrored_transforms_are_refused_by_name() {
    let mut world = World::new(CrowdConfig::default(), PoseConvention::RestTimesPose);
    let mut global = placed(Vec3::ZERO, 0.0);
    global.basis *= Mat3::from_diagonal(Vec3::new(-1.0, 1.0, 1.0));
    let skeleton = FakeSkeleton::human(PoseConvention::RestTimesPose, global, 1.0);
    let error = world.add(skeleton).unwrap_err().to_string();
    assert!(
        error.contains("mirrored") && error.contains("positive scales"),
        "{error}"
    );
    // Mirrored after registration: stalled, reported, bones left alone.
    world
        .add(FakeSkeleton::human(
            PoseConvention::RestTimesPose,
            placed(Vec3::ZERO, 0.0),
            1.0,
        ))
        .unwrap();
    world.frame(1.0 / 30.0);
    world.skeletons[0].global.basis *= Mat3::from_diagonal(Vec3::new(1.0, 1.0, -1.0));
    let writes = world.skeletons[0].writes;
    let error = world
        .crowd
        .read_character(0, &world.skeletons[0], &world.nodes[0])
        .unwrap_err();
    assert!(error.to_string().contains("mirrored"), "{error}");
    world.frame(1.0 / 30.0);
    assert_eq!(world.skeletons[0].writes, writes);
    // A mirrored chain bone pose too.
    world.skeletons[0].global = placed(Vec3::ZERO, 0.0);
    world.frame(1.0 / 30.0);
    let head = world.skeletons[0].bone("Head");
    world.skeletons[0].poses[head].basis = Mat3::from_diagonal(Vec3::new(1.0, -1.0, 1.0));
    let error = world
        .crowd
        .read_character(0, &world.skeletons[0], &world.nodes[0])
        .unwrap_err();
    assert!(
        error.to_string().contains("bone Head's pose is mirrored"),
        "{error}"
    );
}

#[test]
fn a_re_parented_head_and_new_settings_map_the_skeleton_again() {
    let mut world = World::new(CrowdConfig::default(), PoseConvention::RestTimesPose);
    world
        .add(FakeSkeleton::human(
            PoseConvention::RestTimesPose,
            placed(Vec3::ZERO, 0.0),
            1.0,
        ))
        .unwrap();
    world.frame(1.0 / 30.0);
    let bones = world.crowd.chain_bones(0).unwrap().to_vec();
    let neck = world.skeletons[0].bone("Neck");
    assert!(bones.contains(&neck));
    // The head hung from the chest: within HIERARCHY_PERIOD frames the neck is out.
    let head = world.skeletons[0].bone("Head");
    let chest = world.skeletons[0].bone("Chest");
    world.skeletons[0].parents[head] = Some(chest);
    for _ in 0..crate::crowd::HIERARCHY_PERIOD {
        world.frame(1.0 / 30.0);
    }
    let bones = world.crowd.chain_bones(0).unwrap().to_vec();
    assert!(!bones.contains(&neck), "{bones:?}");
    assert!(pose_error(&world, 0) < 1e-5);
    // A new bone map: the eyes left out.
    let skeleton = world.skeletons[0].clone();
    let settings = CharacterSettings::new("LeftEye=none,RightEye=none", 2.0).unwrap();
    world
        .crowd
        .update_character(1000, &skeleton, &Xform::IDENTITY, &settings)
        .unwrap();
    assert_eq!(world.crowd.chain_bones(0).unwrap().len(), bones.len() - 2);
    // A bone map that does not map: refused, the character keeps its chain.
    let headless = CharacterSettings::new("Head=none", 2.0).unwrap();
    let error = world
        .crowd
        .update_character(1000, &skeleton, &Xform::IDENTITY, &headless)
        .unwrap_err();
    assert!(error.to_string().contains("no head bone"), "{error}");
    assert_eq!(world.crowd.chain_bones(0).unwrap().len(), bones.len() - 2);
    assert!(CharacterSettings::new("", -1.0)
        .unwrap_err()
        .to_string()
        .contains("impact = -1"));
    // A skeleton that loses its head: reported once, the character stalls, bones alone.
    world.skeletons[0].names[head] = "Skull".into();
    world.skeletons[0].names.push("Extra".into());
    world.skeletons[0].parents.push(Some(0));
    world.skeletons[0].rests.push(Xform::IDENTITY);
    world.skeletons[0].poses.push(Xform::IDENTITY);
    let error = world
        .crowd
        .read_character(0, &world.skeletons[0], &world.nodes[0])
        .unwrap_err();
    assert!(error.to_string().contains("no head bone"), "{error}");
    assert!(world
        .crowd
        .read_character(0, &world.skeletons[0], &world.nodes[0])
        .is_ok());
    let writes = world.skeletons[0].writes;
    world.frame(1.0 / 30.0);
    assert_eq!(world.skeletons[0].writes, writes);
}

#[test]
fn target_settings_change_live() {
    let mut crowd =
        SceneCrowd::<u32>::new(CrowdConfig::default(), PoseConvention::RestTimesPose).unwrap();
    crowd.add_target(7, 0, &Xform::IDENTITY, 1.0, 1.0).unwrap();
    crowd.update_target(7, 2.5, 4.0).unwrap();
    assert_eq!(crowd.target_look_at_height(0).unwrap(), 2.5);
    assert!(crowd.update_target(7, 2.5, -4.0).is_err());
    assert!(crowd.update_target(8, 2.5, 4.0).is_err());
}

#[test]
fn a_3000_bone_skeleton_without_a_head_gives_a_short_message() {
    let mut skeleton = FakeSkeleton::human(PoseConvention::RestTimesPose, Xform::IDENTITY, 1.0);
    skeleton.names.clear();
    skeleton.parents.clear();
    skeleton.rests.clear();
    skeleton.poses.clear();
    for bone in 0..3000_usize {
        skeleton.names.push(format!(
            "a_rather_long_bone_name_from_an_exporter_{bone:04}_{}",
            "x".repeat(150)
        ));
        skeleton.parents.push(bone.checked_sub(1));
        skeleton.rests.push(Xform::from_rotation_translation(
            Quat::IDENTITY,
            Vec3::Y * 0.01,
        ));
        skeleton.poses.push(Xform::IDENTITY);
    }
    let mut crowd =
        SceneCrowd::<u32>::new(CrowdConfig::default(), PoseConvention::RestTimesPose).unwrap();
    let error = crowd
        .add_character(
            1,
            0,
            &skeleton,
            &Xform::IDENTITY,
            &CharacterSettings::default(),
        )
        .unwrap_err()
        .to_string();
    assert!(
        error.contains("no head bone") && error.contains("more"),
        "{error}"
    );
    let text = crate::report::message("/root/Node", "CrowdGazeCharacter._enter_tree", &error, "");
    assert!(text.len() < 2000, "{} bytes", text.len());
}

/// A skeleton from one of the repository's rig fixtures (`tests/data/rigs/*.rig`: Z up,
/// facing -Y, centimetres for the ones used here), turned to Godot's axes (Y up, facing
/// +Z, metres), rests without rotation, placed at `global`.
pub(crate) fn rig_skeleton(text: &str, convention: PoseConvention, global: Xform) -> FakeSkeleton {
    let mut skeleton = FakeSkeleton::empty(convention, global);
    for line in text.lines() {
        let fields: Vec<&str> = line.split_whitespace().collect();
        if fields.first() != Some(&"bone") {
            continue;
        }
        let [x, y, z] = [fields[3], fields[4], fields[5]].map(|v| v.parse::<f32>().unwrap());
        let parent = skeleton.names.iter().position(|n| n == fields[2]);
        let rest = Xform::from_rotation_translation(Quat::IDENTITY, Vec3::new(x, z, -y) * 0.01);
        skeleton.push(fields[1], parent, rest);
    }
    skeleton
}

#[test]
fn eyes_under_a_facial_bone_look_at_the_target() {
    // Character Creator 4: the eyes hang from CC_Base_FacialBone under the head.
    let rig = include_str!("../../../../tests/data/rigs/cc4.rig");
    assert!(rig.contains("# up: +z") && rig.contains("# forward: -y"));
    for convention in [PoseConvention::RestTimesPose, PoseConvention::PoseIsLocal] {
        let mut world = World::new(CrowdConfig::default(), convention);
        let place = placed(Vec3::new(-1.0, 0.0, 0.5), -0.4);
        let mut skeleton = rig_skeleton(rig, convention, place);
        let facial = skeleton.bone("CC_Base_FacialBone");
        // The face rig turns the facial bone: the eyes must still find the target.
        skeleton.animate(facial, Quat::from_euler(EulerRot::YXZ, 0.15, -0.1, 0.05));
        let id = world.add(skeleton).unwrap();
        let report = world.crowd.mapping_report(0).unwrap().to_string();
        assert!(
            report.contains("'CC_Base_L_Eye'") && report.contains("2 eyes"),
            "{report}"
        );
        let names: Vec<&str> = world
            .crowd
            .chain_bones(0)
            .unwrap()
            .iter()
            .map(|&b| world.skeletons[0].names[b].as_str())
            .collect();
        assert_eq!(
            &names[names.len() - 2..],
            ["CC_Base_L_Eye", "CC_Base_R_Eye"]
        );
        let point = place.transform_point(Vec3::new(0.8, 1.9, 2.0));
        world
            .crowd
            .crowd_mut()
            .set_gaze_target(id, ExplicitTarget::Point(point), TargetPriority::Override)
            .unwrap();
        let mut held = 0;
        for frame in 0..120 {
            // The facial bone keeps moving under the gaze.
            let turn = Quat::from_rotation_x(0.05 * (frame as f32 * 0.3).sin());
            world.skeletons[0].animate(facial, turn);
            world.frame(1.0 / 30.0);
            if world.crowd.is_holding(0).unwrap() {
                held += 1;
                let eyes = ["CC_Base_L_Eye", "CC_Base_R_Eye"];
                let error = eyes_error(&world.skeletons[0], eyes, point).to_degrees();
                assert!(error < 0.5, "{convention:?}: the eyes are {error}° off");
            }
        }
        assert!(held > 30, "{convention:?}: held for {held} frames");
        // The facial bone is read, never written.
        let mut s = world.skeletons[0].clone();
        s.animate(facial, Quat::from_rotation_x(0.05 * (119.0f32 * 0.3).sin()));
        assert_eq!(world.skeletons[0].poses[facial], s.poses[facial]);
    }
}

mod controls;
