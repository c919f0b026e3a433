//! Helpers shared by integration tests (each test binary uses its own part): a crowd driven
//! through the C API — the street of `crowdgaze::scenario` pushed with `cg_crowd_push_frame`
//! — and the real ETH trajectories of the development workspace.
#![allow(dead_code)]
// The `unsafe { cg_... }` calls below pass pointers to live values of the sizes the header
// asks for, or deliberately bad ones (NULL, misaligned, wrong struct_size) that the library
// must refuse: that is their safety comment, once for the file.
#![allow(clippy::undocumented_unsafe_blocks)]

pub mod field;
pub mod rig;

use crowdgaze::ffi::attention::*;

use crowdgaze::ffi::crowd::*;
use crowdgaze::ffi::frame::*;
use crowdgaze::ffi::last_error::last_error_message;
use crowdgaze::ffi::status::cg_status;
use crowdgaze::scenario::{Activity, Scenario};
use crowdgaze::World;
use glam::{Vec2, Vec3};
use std::mem::MaybeUninit;
use std::ptr::null_mut;

/// `shared/data/pedestrians/eth_seq_eth.csv` beside the repository.
pub const ETH_SEQ_ETH: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../shared/data/pedestrians/eth_seq_eth.csv"
);

/// Reads `frame,id,x,y` rows.
pub fn read_trajectories(path: &str) -> Vec<(u32, u32, f32, f32)> {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| {
        panic!("{path}: {e} (the tests need ../shared/data beside the repository)")
    });
    text.lines()
        .skip(1)
        .map(|line| {
            let fields: Vec<&str> = line.split(',').collect();
            (
                fields[0].parse().unwrap(),
                fields[1].parse().unwrap(),
                fields[2].parse().unwrap(),
                fields[3].parse().unwrap(),
            )
        })
        .collect()
}

/// Fails with the library's message unless `status` is `CG_STATUS_OK`.
pub fn check(status: cg_status, what: &str) {
    assert_eq!(status, cg_status::Ok, "{what}: {}", last_error_message());
}

/// A struct filled by its `_init` function (after setting its `struct_size`).
pub fn init<T>(f: unsafe extern "C" fn(*mut T) -> cg_status) -> T {
    let mut value = MaybeUninit::<T>::uninit();
    // SAFETY: every versioned struct starts with `uint32_t struct_size`, which the caller
    // sets to its size before the `_init` call.
    unsafe {
        value
            .as_mut_ptr()
            .cast::<u32>()
            .write(std::mem::size_of::<T>() as u32)
    };
    check(unsafe { f(value.as_mut_ptr()) }, "init");
    // SAFETY: initialised by the _init function just above.
    unsafe { value.assume_init() }
}

/// A crowd created through the C API, destroyed on drop.
pub struct CrowdHandle(*mut cg_crowd);

impl CrowdHandle {
    pub fn new(config: &cg_crowd_config) -> CrowdHandle {
        let mut handle = null_mut();
        check(
            unsafe { cg_crowd_create(config, &mut handle) },
            "cg_crowd_create",
        );
        CrowdHandle(handle)
    }

    pub fn as_mut(&self) -> *mut cg_crowd {
        self.0
    }

    pub fn as_const(&self) -> *const cg_crowd {
        self.0
    }

    /// A character of the default chain and model at `position` (the crowd's units).
    pub fn add_character(&self, position: Vec3, heading: f32) -> u32 {
        let mut desc: cg_character_desc = init(cg_character_desc_init);
        desc.position = position.into();
        desc.heading = heading;
        let mut id = 0;
        check(
            unsafe { cg_crowd_add_character(self.0, &desc, &mut id) },
            "cg_crowd_add_character",
        );
        id
    }

    pub fn remove(&self, id: u32) {
        check(
            unsafe { cg_crowd_remove_entity(self.0, id) },
            "cg_crowd_remove_entity",
        );
    }

    /// Pushes `states` at time `t`, then steps the crowd by `dt`.
    pub fn push_and_step(&self, t: f64, dt: f32, states: &[cg_entity_state]) {
        check(
            unsafe { cg_crowd_push_frame(self.0, t, states.as_ptr(), states.len()) },
            "cg_crowd_push_frame",
        );
        check(unsafe { cg_crowd_step(self.0, dt) }, "cg_crowd_step");
    }
}

impl Drop for CrowdHandle {
    fn drop(&mut self) {
        unsafe { cg_crowd_destroy(self.0) };
    }
}

/// The state of entity `id`: `CG_STATE_HEADING_FROM_MOTION` if `walking`, else `heading`.
pub fn entity_state(id: u32, heading: f32, walking: bool) -> cg_entity_state {
    let mut state: cg_entity_state = init(cg_entity_state_init);
    state.id = id;
    state.heading = heading;
    if walking {
        state.flags = CG_STATE_HEADING_FROM_MOTION;
    }
    state
}

/// A scenario's ground point (along forward, along side) in `world`.
fn on_ground(world: &World, p: Vec2) -> Vec3 {
    world.forward * p.x + world.side * p.y
}

/// Grillon & Thalmann's street (`Scenario::street`: people walking, standing and sitting,
/// props along both sides, `d_m` = 10 m) run through the C API: the scenario moves the
/// people, their states go in with `cg_crowd_push_frame`, then `cg_crowd_step`. The
/// crowd's axes are the defaults (Y up, Z forward), metres; it records up to
/// `recorded_states` states for `cg_crowd_plan`.
pub struct Street {
    pub crowd: CrowdHandle,
    scenario: Scenario,
    world: World,
    states: Vec<cg_entity_state>,
    time: f64,
}

impl Street {
    /// 30 frames per second.
    pub const DT: f32 = 1.0 / 30.0;

    pub fn new(characters: usize, objects: usize, seed: u64, recorded_states: u32) -> Street {
        let mut config: cg_crowd_config = init(cg_crowd_config_init);
        config.seed = seed;
        config.max_recorded_states = recorded_states;
        config.max_characters = characters as u32;
        config.max_objects = objects as u32;
        let crowd = CrowdHandle::new(&config);
        let world = World::default();
        let ground = |p: Vec2| on_ground(&world, p);
        let scenario = Scenario::street(characters, objects, seed);
        for prop in &scenario.props {
            let mut desc: cg_object_desc = init(cg_object_desc_init);
            desc.position = ground(prop.position).into();
            desc.heading = prop.heading;
            desc.look_at_height = prop.look_at_height;
            desc.impact = prop.impact;
            let mut id = 0;
            check(
                unsafe { cg_crowd_add_object(crowd.as_mut(), &desc, &mut id) },
                "cg_crowd_add_object",
            );
        }
        let states = scenario
            .people
            .iter()
            .map(|person| {
                let id = crowd.add_character(ground(person.position), person.heading);
                entity_state(id, person.heading, person.activity == Activity::Walking)
            })
            .collect();
        Street {
            crowd,
            scenario,
            world,
            states,
            time: 0.0,
        }
    }

    /// Moves the people by [`Street::DT`], pushes their states and steps the crowd.
    pub fn frame(&mut self) {
        self.scenario.advance(Self::DT);
        for (state, person) in self.states.iter_mut().zip(&self.scenario.people) {
            state.position = on_ground(&self.world, person.position).into();
        }
        self.time += f64::from(Self::DT);
        self.crowd.push_and_step(self.time, Self::DT, &self.states);
    }
}

/// Puts the characters `ids` on the crowd, saliency, baseline and street models in turn
/// (character `i` on model `i % 4`), so that a test steps all four side by side.
pub fn mix_attention_models(crowd: &mut crowdgaze::Crowd, ids: &[u32]) {
    use crowdgaze::attention::{AttentionModel, CharacterParams};
    let models = [
        AttentionModel::Crowd,
        AttentionModel::Saliency,
        AttentionModel::Baseline,
        AttentionModel::Street,
    ];
    for (i, &id) in ids.iter().enumerate() {
        let params = crowd.character_params(id).unwrap();
        let model = models[i % models.len()];
        crowd
            .set_character_params(id, &CharacterParams { model, ..params })
            .unwrap();
    }
}

/// The settings of [`mixed_street`]'s crowd but for what a test varies: a level of detail by
/// distance, attention every second step, gaze following on.
pub fn mixed_street_config() -> crowdgaze::CrowdConfig {
    crowdgaze::CrowdConfig {
        lod_distance: 12.0,
        attention_period: 2,
        following: crowdgaze::attention::following::FollowConfig {
            enabled: true,
            ..crowdgaze::attention::following::FollowConfig::MILGRAM
        },
        ..crowdgaze::CrowdConfig::default()
    }
}

/// Gaze chains of every shape the gaze IK steps side by side in one batch, in `world`'s
/// axes: the human chain; head and eyes alone (empty spine and neck); the human chain
/// without eyes; a short chain (2 spine, 1 cervical, head, eyes) with rest rotations; a
/// neck and head without spine or eyes.
pub fn varied_chains(world: &World) -> Vec<crowdgaze::ik::GazeChain> {
    use crowdgaze::ik::{ChainJoint, GazeChain};
    let human = GazeChain::human(world.up, world.forward);
    let joints = human.joints();
    let (up, forward) = (world.up, world.forward);
    let chain = |joints: &[ChainJoint], root: f32| {
        GazeChain::new(joints, forward, up, up * root).expect("a valid test chain")
    };
    let head = |joint: ChainJoint, offset: f32| ChainJoint {
        offset: up * offset,
        ..joint
    };
    let tilted = |joint: ChainJoint, degrees: f32| ChainJoint {
        rest: glam::Quat::from_axis_angle(world.side, degrees.to_radians()),
        ..joint
    };
    vec![
        human,
        chain(&[head(joints[7], 0.61), joints[8], joints[9]], 0.95),
        chain(&joints[..8], 0.95),
        chain(
            &[
                tilted(joints[0], 4.0),
                head(joints[1], 0.25),
                tilted(joints[5], -3.0),
                head(joints[7], 0.2),
                joints[8],
                joints[9],
            ],
            0.95,
        ),
        chain(&[joints[5], joints[6], joints[7]], 1.46),
    ]
}

/// Gives character `id` a base pose: a small bend of each joint, one of five by `variant`.
pub fn bend(crowd: &mut crowdgaze::Crowd, id: u32, variant: usize) {
    let joints = crowd.chain(id).unwrap().joint_count();
    let side = crowd.config().world.side;
    let pose: Vec<glam::Quat> = (0..joints)
        .map(|joint| {
            let angle = 0.02 * (1 + (variant + joint) % 5) as f32;
            glam::Quat::from_axis_angle(side, angle)
        })
        .collect();
    crowd.set_base_pose(id, &pose).unwrap();
}

/// Gives every third character of `ids` a base pose ([`bend`]).
pub fn set_base_poses(crowd: &mut crowdgaze::Crowd, ids: &[u32]) {
    for (i, &id) in ids.iter().enumerate().filter(|(i, _)| i % 3 == 1) {
        bend(crowd, id, i);
    }
}

/// A street crowd of `people` and `props` (seed `seed`) mixing the four attention models,
/// the gaze chains of [`varied_chains`] in turn and base poses on every third character,
/// with an explicit target of each priority and three people staring up (whom the others
/// may follow, when the config turns following on): with a viewer set by the test, every
/// path of a character's step.
pub fn mixed_street(
    config: crowdgaze::CrowdConfig,
    people: usize,
    props: usize,
    seed: u64,
) -> (crowdgaze::Crowd, Scenario) {
    use crowdgaze::crowd::{ExplicitTarget, TargetPriority};
    let mut crowd = crowdgaze::Crowd::new(config).unwrap();
    let chains = varied_chains(&crowd.config().world);
    let mut scenario = Scenario::street(people, props, seed).with_chains(chains);
    scenario.populate(&mut crowd).unwrap();
    let ids = scenario.character_ids().to_vec();
    mix_attention_models(&mut crowd, &ids);
    set_base_poses(&mut crowd, &ids);
    crowd
        .set_gaze_target(
            ids[7],
            ExplicitTarget::Point(Vec3::new(3.0, 2.0, 3.0)),
            TargetPriority::Override,
        )
        .unwrap();
    crowd
        .set_gaze_target(
            ids[8],
            ExplicitTarget::Entity(ids[9]),
            TargetPriority::WhenIdle,
        )
        .unwrap();
    for &starer in ids.iter().skip(15).step_by(8).take(3) {
        crowd
            .set_gaze_target(
                starer,
                ExplicitTarget::Point(Vec3::new(0.0, 9.0, 20.0)),
                TargetPriority::Override,
            )
            .unwrap();
    }
    (crowd, scenario)
}

/// Every output of every character in the crowd's character order, as bits: gaze info,
/// eyes, eyelids, and the final joints read by range.
pub fn output_bits(crowd: &crowdgaze::Crowd) -> Vec<u32> {
    let mut bits = Vec::new();
    for character in 0..crowd.character_count() {
        let gaze = crowd.gaze_at(character);
        bits.extend([
            gaze.character,
            gaze.target,
            gaze.head_target,
            gaze.interest_count,
        ]);
        bits.extend(gaze.target_position.to_array().map(f32::to_bits));
        bits.extend([gaze.s_max, gaze.threshold, gaze.attentive_fraction].map(f32::to_bits));
        let eyes = crowd.eyes_at(character);
        for vector in eyes.origins.iter().chain(&eyes.directions) {
            bits.extend(vector.to_array().map(f32::to_bits));
        }
        let lids = crowd.eyelids_at(character);
        bits.push(lids.character);
        bits.extend(
            [
                lids.left_closure,
                lids.right_closure,
                lids.left_lid_pitch,
                lids.right_lid_pitch,
            ]
            .map(f32::to_bits),
        );
    }
    let count = crowd.character_count();
    let mut joints = vec![glam::Quat::IDENTITY; crowd.joint_total(0, count).unwrap()];
    crowd.read_joints(0, count, false, &mut joints).unwrap();
    bits.extend(joints.iter().flat_map(|q| q.to_array().map(f32::to_bits)));
    bits
}

/// Asserts two runs' outputs (one `Vec` per frame) are equal, naming the first frame that
/// differs.
pub fn assert_same(expected: &[Vec<u32>], actual: &[Vec<u32>], what: &str) {
    assert_eq!(expected.len(), actual.len());
    for (frame, (expected, actual)) in expected.iter().zip(actual).enumerate() {
        assert!(expected == actual, "{what}: frame {frame} differs");
    }
}
