//! The fixture: a populated crowd, three view blenders, and the caller's output buffers.

use crate::{
    frames::MOVERS,
    joints::ALL_JOINTS,
    skeleton::Skeleton,
    snapshot::{blender_snapshot, crowd_snapshot, rig_snapshot, status, Snapshot},
    values::{init, ok, rotation, transform, vec3},
};
use crowdgaze::ffi::attention::*;
use crowdgaze::ffi::chain::*;
use crowdgaze::ffi::conversations::*;
use crowdgaze::ffi::crowd::*;
use crowdgaze::ffi::eyelids::cg_eyelids;
use crowdgaze::ffi::frame::*;
use crowdgaze::ffi::gaze::*;
use crowdgaze::ffi::rig::{cg_rig, cg_rig_destroy};
use crowdgaze::ffi::types::{cg_axis, cg_dualquat, cg_quat, cg_vec3};
use crowdgaze::ffi::view_blender::*;
use std::mem::{size_of, MaybeUninit};
use std::ptr::{null, null_mut};

/// The state a case starts from.
#[derive(Clone, Copy, PartialEq, Eq, Hash, Debug)]
pub(crate) enum Setup {
    /// Characters (three attention models, two chains) and objects below capacity, a
    /// viewer, explicit targets, a base pose, a removed character and object, a conversation
    /// of characters 0 and 1 (1 talking) and two that ended, recording on, a few frames
    /// pushed and stepped.
    Online,
    /// `Online`, then planned (`cg_crowd_plan`) and stepped along the plan.
    Planned,
    /// `Online` with as many characters, objects and conversations as the capacities allow.
    Full,
    /// `Online` with the recording exactly full.
    RecordingFull,
    /// `Online` without recording and without a viewer.
    Unrecorded,
}

pub(crate) const FPS: f64 = 30.0;
const FRAMES: usize = 6;
pub(crate) const UNKNOWN_ID: u32 = 123_456_789;
/// `max_conversations` of every setup but `Full` (which has 1).
pub(crate) const MAX_CONVERSATIONS: u32 = 4;
pub(crate) const JOINTS: usize = 3;
pub(crate) const KEYS: usize = 3;

/// An entity of the fixture and how it moves: `start + velocity · t`.
#[derive(Clone, Copy)]
struct Mover {
    id: u32,
    start: [f32; 3],
    velocity: [f32; 3],
    heading: f32,
    flags: u32,
}

impl Mover {
    /// An entity standing at `start`, heading 1 rad.
    fn still(id: u32, start: [f32; 3]) -> Mover {
        Mover {
            id,
            start,
            velocity: [0.0; 3],
            heading: 1.0,
            flags: 0,
        }
    }
}

/// Output buffers handed to the functions; filled with a pattern that a failed call must
/// leave as it is.
#[repr(C)]
pub(crate) struct Outputs {
    /// Arrays: the crowd's readers, a matrix, the view blender's weights and poses.
    pub(crate) gaze: [cg_gaze_info; 8],
    pub(crate) constraints: [cg_constraint; 8],
    pub(crate) quats: [cg_quat; 64],
    pub(crate) eyes: [cg_eye_info; 8],
    pub(crate) eyelids: [cg_eyelids; 8],
    pub(crate) matrix: [f32; 16],
    pub(crate) weights: [f32; 8],
    pub(crate) pose: [cg_dualquat; 8],
    /// Single values: `*out_id`, `*out_count` (and totals), new handles, filled structs,
    /// transforms and their parts.
    pub(crate) id: u32,
    pub(crate) count: usize,
    pub(crate) crowd: *mut cg_crowd,
    pub(crate) blender: *mut cg_view_blender,
    pub(crate) rig: *mut cg_rig,
    /// Bone indices and roles of a rig.
    pub(crate) bones: [u32; 80],
    pub(crate) crowd_config: cg_crowd_config,
    pub(crate) chain: cg_chain_desc,
    pub(crate) params: cg_character_params,
    pub(crate) score: cg_score_breakdown,
    pub(crate) dual_quat: cg_dualquat,
    pub(crate) quat: cg_quat,
    pub(crate) vec3: cg_vec3,
    /// `*out_following` and `*out_glances` of `cg_crowd_read_following`.
    pub(crate) following: [u32; 2],
}

impl Outputs {
    fn new() -> Box<Outputs> {
        let mut out = Box::<Outputs>::new_uninit();
        // SAFETY: every field is an integer, a float or a raw pointer, for which any bytes
        // are a valid value; write_bytes initialises all of them (and the padding).
        unsafe {
            out.as_mut_ptr().write_bytes(0xA5, 1);
            out.assume_init()
        }
    }

    fn bytes(&self) -> &[u8] {
        // SAFETY: every byte was initialised by `new`; a failed call writes nothing.
        unsafe {
            std::slice::from_raw_parts((self as *const Outputs).cast::<u8>(), size_of::<Outputs>())
        }
    }
}

pub(crate) struct Harness {
    pub(crate) crowd: *mut cg_crowd,
    /// Live characters: a crowd-model one, one with a chain without eyes, a saliency-model
    /// one, a baseline-model one.
    characters: Vec<u32>,
    /// Live objects.
    objects: Vec<u32>,
    movers: Vec<Mover>,
    pub(crate) viewer: Option<u32>,
    pub(crate) removed_character: u32,
    pub(crate) removed_object: u32,
    /// The live conversation, of characters 0 and 1.
    pub(crate) conversation: u32,
    /// Conversations that ended: one left with one member when the removed character went,
    /// one removed with `cg_crowd_remove_conversation`.
    pub(crate) ended_conversations: [u32; 2],
    /// Time of the last pushed frame.
    pub(crate) time: f64,
    pub(crate) blender: *mut cg_view_blender,
    /// Every key has a clip, no key camera.
    pub(crate) blender_no_camera: *mut cg_view_blender,
    /// Key cameras, but key 1 has no clip.
    pub(crate) blender_no_clip: *mut cg_view_blender,
    /// The rig of the Mixamo skeleton (`rig::Skeleton::mixamo`), for a crowd in metres.
    pub(crate) rig: *mut cg_rig,
    pub(crate) out: Box<Outputs>,
    /// Problems a case found beyond its status (an input changed, …).
    pub(crate) problems: Vec<String>,
}

impl Drop for Harness {
    fn drop(&mut self) {
        unsafe { cg_crowd_destroy(self.crowd) };
        for blender in [self.blender, self.blender_no_camera, self.blender_no_clip] {
            unsafe { cg_view_blender_destroy(blender) };
        }
        unsafe { cg_rig_destroy(self.rig) };
    }
}

/// The chain of the second character: the human chain without its eyes (8 joints).
fn chain_without_eyes() -> cg_chain_desc {
    let mut chain = MaybeUninit::<cg_chain_desc>::uninit();
    // SAFETY: a versioned struct starts with its `uint32_t struct_size`, set before the call.
    unsafe {
        chain
            .as_mut_ptr()
            .cast::<u32>()
            .write(std::mem::size_of::<cg_chain_desc>() as u32)
    };
    ok(unsafe {
        cg_chain_desc_init_human(
            chain.as_mut_ptr(),
            cg_axis::PositiveY as u32,
            cg_axis::PositiveZ as u32,
        )
    });
    // SAFETY: written by the successful call.
    let mut chain = unsafe { chain.assume_init() };
    chain.joint_count = 8;
    chain
}

pub(crate) fn human_chain() -> cg_chain_desc {
    let mut chain = chain_without_eyes();
    chain.joint_count = 10;
    chain
}

/// A base pose for a 10-joint chain, every joint turned a little.
pub(crate) fn base_pose() -> [cg_quat; 10] {
    std::array::from_fn(|joint| rotation([0.0, 1.0, 0.0], 0.02 * (joint as f32 + 1.0)))
}

impl Harness {
    pub(crate) fn new(setup: Setup) -> Harness {
        let mut config: cg_crowd_config = init(cg_crowd_config_init);
        config.max_characters = if setup == Setup::Full { 4 } else { 6 };
        config.max_objects = if setup == Setup::Full { 2 } else { 3 };
        config.max_conversations = if setup == Setup::Full {
            1
        } else {
            MAX_CONVERSATIONS
        };
        config.max_recorded_states = match setup {
            Setup::Unrecorded => 0,
            Setup::RecordingFull => (6 * FRAMES) as u32,
            _ => 10_000,
        };
        let mut crowd = null_mut();
        ok(unsafe { cg_crowd_create(&config, &mut crowd) });
        let mut h = Harness {
            crowd,
            characters: Vec::new(),
            objects: Vec::new(),
            movers: Vec::new(),
            viewer: None,
            removed_character: 0,
            removed_object: 0,
            conversation: 0,
            ended_conversations: [0; 2],
            time: 0.0,
            blender: Harness::blender(true, [true; KEYS]),
            blender_no_camera: Harness::blender(false, [true; KEYS]),
            blender_no_clip: Harness::blender(true, [true, false, true]),
            rig: Skeleton::mixamo().rig(1.0).into_raw(),
            out: Outputs::new(),
            problems: Vec::new(),
        };
        let no_eyes = chain_without_eyes();
        let crowd_model = cg_attention_model::Crowd as u32;
        h.add_character([0.0, 0.0, 0.0], [1.0, 0.0, 0.2], 0, crowd_model, null());
        let talker = h.add_character(
            [1.5, 0.0, 2.0],
            [0.0, 0.0, -0.8],
            CG_STATE_HEADING_FROM_MOTION | CG_STATE_TALKING,
            crowd_model,
            &no_eyes,
        );
        h.removed_character = h.add_character([5.0, 0.0, 5.0], [0.0; 3], 0, crowd_model, null());
        h.ended_conversations[0] = h.converse(&[talker, h.removed_character]);
        h.remove(h.removed_character);
        h.add_character(
            [-1.0, 0.0, 3.0],
            [0.5, 0.0, 0.5],
            CG_STATE_HAS_VELOCITY,
            cg_attention_model::Saliency as u32,
            null(),
        );
        h.add_character(
            [2.0, 0.0, -1.0],
            [0.0; 3],
            0,
            cg_attention_model::Baseline as u32,
            null(),
        );
        h.add_object([0.0, 1.0, 4.0], 2.0);
        h.removed_object = h.add_object([4.0, 0.0, 0.0], 1.0);
        h.remove(h.removed_object);
        h.add_object([-3.0, 0.0, 1.0], 0.5);
        if setup != Setup::Unrecorded {
            let mut viewer = 0;
            ok(unsafe { cg_crowd_set_viewer(crowd, &vec3(0.0, 1.7, 6.0), 1.5, &mut viewer) });
            h.viewer = Some(viewer);
        }
        let [c0, c1, c3, c4] = h.characters[..] else {
            unreachable!("four characters")
        };
        h.ended_conversations[1] = h.converse(&[c3, c4]);
        ok(unsafe { cg_crowd_remove_conversation(crowd, h.ended_conversations[1]) });
        h.conversation = h.converse(&[c0, c1]);
        let mut target: cg_gaze_target = init(cg_gaze_target_init);
        target.kind = CG_GAZE_TARGET_ENTITY;
        target.entity = h.objects[0];
        target.priority = CG_GAZE_PRIORITY_WHEN_IDLE;
        ok(unsafe { cg_crowd_set_gaze_target(crowd, c1, &target) });
        target.kind = CG_GAZE_TARGET_POINT;
        target.point = vec3(3.0, 1.5, 3.0);
        target.priority = CG_GAZE_PRIORITY_OVERRIDE;
        ok(unsafe { cg_crowd_set_gaze_target(crowd, c0, &target) });
        ok(unsafe { cg_crowd_set_base_pose(crowd, c4, base_pose().as_ptr(), 10) });
        ok(unsafe { cg_crowd_set_attention_period(crowd, c3, 2) });
        for frame in 0..FRAMES {
            h.time = frame as f64 / FPS;
            let states = h.frame_at(h.time);
            ok(unsafe { cg_crowd_push_frame(crowd, h.time, states.as_ptr(), states.len()) });
            ok(unsafe { cg_crowd_step(crowd, (1.0 / FPS) as f32) });
        }
        assert_eq!(h.movers.len(), MOVERS, "entities in a frame");
        let mut joints = 0;
        ok(unsafe { cg_crowd_joint_total(crowd, 0, 4, &mut joints) });
        assert_eq!(joints, ALL_JOINTS, "joints of the four characters");
        if setup == Setup::Planned {
            ok(unsafe { cg_crowd_plan(crowd) });
            ok(unsafe { cg_crowd_step(crowd, (1.0 / FPS) as f32) });
            ok(unsafe { cg_crowd_step(crowd, (1.0 / FPS) as f32) });
        }
        h
    }

    fn add_character(
        &mut self,
        start: [f32; 3],
        velocity: [f32; 3],
        flags: u32,
        model: u32,
        chain: *const cg_chain_desc,
    ) -> u32 {
        let heading = 0.3 * self.movers.len() as f32;
        let mut desc: cg_character_desc = init(cg_character_desc_init);
        desc.position = vec3(start[0], start[1], start[2]);
        desc.heading = heading;
        desc.attention_model = model;
        desc.chain = chain;
        let mut id = 0;
        ok(unsafe { cg_crowd_add_character(self.crowd, &desc, &mut id) });
        self.characters.push(id);
        self.track(Mover {
            velocity,
            heading,
            flags,
            ..Mover::still(id, start)
        })
    }

    /// Makes `members` a conversation; returns its id.
    fn converse(&mut self, members: &[u32]) -> u32 {
        let mut group = 0;
        ok(unsafe {
            cg_crowd_set_conversation(self.crowd, members.as_ptr(), members.len(), &mut group)
        });
        group
    }

    /// Remembers how a new entity moves; returns its id.
    fn track(&mut self, mover: Mover) -> u32 {
        self.movers.push(mover);
        mover.id
    }

    fn add_object(&mut self, start: [f32; 3], impact: f32) -> u32 {
        let mut desc: cg_object_desc = init(cg_object_desc_init);
        desc.position = vec3(start[0], start[1], start[2]);
        desc.impact = impact;
        desc.look_at_height = 1.2;
        let mut id = 0;
        ok(unsafe { cg_crowd_add_object(self.crowd, &desc, &mut id) });
        self.objects.push(id);
        self.track(Mover::still(id, start))
    }

    fn remove(&mut self, id: u32) {
        ok(unsafe { cg_crowd_remove_entity(self.crowd, id) });
        self.characters.retain(|&c| c != id);
        self.objects.retain(|&o| o != id);
        self.movers.retain(|m| m.id != id);
    }

    /// A view blender of `JOINTS` joints and `KEYS` keys: key 0 a looping clip, key 1 a
    /// pose, key 2 a clamped clip (those `clips` says), and cameras (if `cameras`) at +Z for
    /// key 0, +X for key 1, −Z and −X for key 2.
    fn blender(cameras: bool, clips: [bool; KEYS]) -> *mut cg_view_blender {
        let mut config: cg_view_blender_config = init(cg_view_blender_config_init);
        config.joint_count = JOINTS as u32;
        config.key_count = KEYS as u32;
        let mut blender = null_mut();
        ok(unsafe { cg_view_blender_create(&config, &mut blender) });
        let frames: Vec<cg_dualquat> = (0..4 * JOINTS)
            .map(|i| transform([0.0, 1.0, 0.0], 0.1 * i as f32, [0.0, 0.1 * i as f32, 0.0]))
            .collect();
        if clips[0] {
            ok(unsafe { cg_view_blender_set_key_clip(blender, 0, frames.as_ptr(), 4, 10.0, true) });
        }
        if clips[1] {
            let pose = [transform([1.0, 0.0, 0.0], 0.4, [0.2, 0.0, 0.0]); JOINTS];
            ok(unsafe { cg_view_blender_set_key_pose(blender, 1, pose.as_ptr(), JOINTS) });
        }
        if clips[2] {
            ok(unsafe {
                cg_view_blender_set_key_clip(blender, 2, frames[JOINTS..].as_ptr(), 2, 2.0, false)
            });
        }
        if cameras {
            for (direction, key) in [
                (vec3(0.0, 0.0, 1.0), 0),
                (vec3(1.0, 0.0, 0.0), 1),
                (vec3(0.0, 0.0, -1.0), 2),
                (vec3(-1.0, 0.0, 0.0), 2),
            ] {
                ok(unsafe { cg_view_blender_add_camera(blender, direction, key) });
            }
        }
        blender
    }

    /// Valid states of every live entity at time `t`.
    pub(crate) fn frame_at(&self, t: f64) -> Vec<cg_entity_state> {
        self.movers
            .iter()
            .map(|m| {
                let mut state: cg_entity_state = init(cg_entity_state_init);
                let t = t as f32;
                state.id = m.id;
                state.flags = m.flags;
                state.heading = m.heading;
                state.position = vec3(
                    m.start[0] + m.velocity[0] * t,
                    m.start[1] + m.velocity[1] * t,
                    m.start[2] + m.velocity[2] * t,
                );
                state.velocity = vec3(m.velocity[0], m.velocity[1], m.velocity[2]);
                state
            })
            .collect()
    }

    /// The next frame's time and states.
    pub(crate) fn next_frame(&self) -> (f64, Vec<cg_entity_state>) {
        let t = self.time + 1.0 / FPS;
        (t, self.frame_at(t))
    }

    /// Every id worth asking about: live, removed, the viewer, unknown, `CG_NO_TARGET`.
    fn ids(&self) -> Vec<u32> {
        let mut ids = self.characters.clone();
        ids.extend(&self.objects);
        ids.extend(self.viewer);
        ids.extend([
            self.removed_character,
            self.removed_object,
            UNKNOWN_ID,
            CG_NO_TARGET,
        ]);
        ids
    }

    pub(crate) fn character(&self, index: usize) -> u32 {
        self.characters[index]
    }

    pub(crate) fn object(&self) -> u32 {
        self.objects[0]
    }

    /// Records a problem a case found besides its status.
    pub(crate) fn note(&mut self, problem: impl Into<String>) {
        self.problems.push(problem.into());
    }

    /// Everything observable, by section.
    pub(crate) fn snapshot(&self) -> Snapshot {
        let mut s = crowd_snapshot(self.crowd, &self.ids());
        for (name, blender) in [
            ("blender", self.blender),
            ("blender_no_camera", self.blender_no_camera),
            ("blender_no_clip", self.blender_no_clip),
        ] {
            blender_snapshot(&mut s, name, blender);
        }
        rig_snapshot(&mut s, self.rig);
        s.section("output buffers").extend(self.out.bytes());
        s
    }

    /// The crowd's next frames and its plan: three frames pushed and stepped, read, then
    /// planned and read again.
    pub(crate) fn future(&self) -> Snapshot {
        let mut s = Snapshot::default();
        let steps = s.section("next frames: statuses");
        for k in 1..=3 {
            let t = self.time + k as f64 / FPS;
            let states = self.frame_at(t);
            status(steps, unsafe {
                cg_crowd_push_frame(self.crowd, t, states.as_ptr(), states.len())
            });
            status(steps, unsafe {
                cg_crowd_step(self.crowd, (1.0 / FPS) as f32)
            });
        }
        for (name, bytes) in crowd_snapshot(self.crowd, &self.ids()).sections {
            s.sections.push((format!("next frames: {name}"), bytes));
        }
        status(s.section("plan"), unsafe { cg_crowd_plan(self.crowd) });
        for (name, bytes) in crowd_snapshot(self.crowd, &self.ids()).sections {
            s.sections.push((format!("planned: {name}"), bytes));
        }
        s
    }
}
