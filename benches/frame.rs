//! What an engine pays per frame, through the C ABI: `cg_crowd_push_frame` (every
//! character's state), `cg_crowd_step`, then `cg_crowd_read_gaze`, `cg_crowd_read_joints`
//! and `cg_crowd_read_eyes` for every character, into buffers the caller allocated once.
//! The crowd is the plaza of random walkers of `benches/attention.rs` (0.25 people/m²,
//! moved 1/30 s per frame), created and filled through the C API (default config but
//! `max_characters` and `threads`), at 1 000, 10 000 and 100 000 characters on 1 and 2
//! threads: the whole frame (`frame_{t}t`), each call alone (`push_`, `step_`,
//! `read_gaze_`, `read_joints_`, `read_eyes_{t}t`; and `cg_crowd_read_eyelids`, which the
//! whole frame leaves out so that its figures stay comparable: `read_eyelids_{t}t`), and, to choose `reorder_period`'s
//! default by the whole frame, the whole frame with the storage reordered every 32 steps
//! (`frame_reorder32_{t}t`) and its push and reads on 1 thread (`push_reorder32_1t`, ...).
//! On 2 threads it also times the push split in two parts pushed from two threads
//! (`cg_crowd_begin_push`, `cg_crowd_push_range`, `cg_crowd_end_push`: `push_ranged_2t`).
//!
//! Engines with their own skeletons also convert each character's bones every frame: the
//! 65-bone Mixamo skeleton of `tests/support/rig.rs`, each character with its own bone
//! array (swayed differently), through `cg_rig_base_pose` (bones to base pose,
//! `rig_base_pose`) and `cg_rig_write_joints` (joints back into the bones, in place,
//! `rig_write_joints`), one rig for all, on 1 thread.
//!
//! Moving the walkers and writing their `cg_entity_state`s (the engine's own work) happens
//! before each timed frame and is not timed; nothing is allocated per frame. Each part is
//! timed as it runs in the engine's frame: the step after a frame whose outputs were read
//! (so it publishes them for the readers), the reads after such a step; and, on 1 thread,
//! the step of a crowd whose outputs nobody reads (`step_unread_1t`, publishing nothing).
//!
//! Run: `cargo bench --bench frame`, or `scripts/bench` for the README's tables. Criterion
//! reports time per crowd frame; throughput in elements = characters. Built as a test
//! (`cargo test --benches`) it runs each function once at 1 000 characters only.

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use crowdgaze::ffi::attention::{
    cg_character_desc, cg_character_desc_init, cg_crowd_add_character, cg_crowd_read_gaze,
    cg_entity_state, cg_entity_state_init, cg_gaze_info, CG_STATE_HAS_VELOCITY,
    CG_STATE_HEADING_FROM_MOTION,
};
use crowdgaze::ffi::crowd::cg_crowd;
use crowdgaze::ffi::crowd::{cg_crowd_config, cg_crowd_config_init};
use crowdgaze::ffi::eyelids::{cg_crowd_read_eyelids, cg_eyelids};
use crowdgaze::ffi::frame::{
    cg_crowd_begin_push, cg_crowd_end_push, cg_crowd_push_frame, cg_crowd_push_range, cg_crowd_step,
};
use crowdgaze::ffi::gaze::{
    cg_crowd_joint_total, cg_crowd_read_eyes, cg_crowd_read_joints, cg_eye_info,
};
use crowdgaze::ffi::rig::{cg_rig_base_pose, cg_rig_write_joints};
use crowdgaze::ffi::status::cg_status;
use crowdgaze::ffi::types::cg_quat;
use crowdgaze::scenario::Scenario;
use crowdgaze::{CrowdConfig, World};
use std::hint::black_box;
use std::sync::mpsc;
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

// The integration tests' C API helpers: `init` (a versioned struct through its `_init`),
// `check` (a status, with the library's message) and `CrowdHandle` (destroyed on drop).
#[path = "../tests/support/mod.rs"]
mod c_api;
use c_api::{check as ok, init, CrowdHandle};

const DENSITY: f32 = 0.25;
const DT: f32 = 1.0 / 30.0;
const WARM_UP_FRAMES: u32 = 40;

/// A second engine thread (as a job system's worker) that pushes a part of a frame on
/// request: a crowd, its states and their count, as addresses.
struct Helper {
    jobs: Option<mpsc::Sender<(usize, usize, usize)>>,
    done: mpsc::Receiver<cg_status>,
    thread: Option<JoinHandle<()>>,
}

impl Helper {
    fn new() -> Helper {
        let (jobs, requests) = mpsc::channel::<(usize, usize, usize)>();
        let (report, done) = mpsc::channel();
        let thread = std::thread::spawn(move || {
            for (crowd, states, count) in requests {
                // SAFETY: the requester keeps the crowd and the states alive, unmoved, and
                // only pushes ranges of the open push until this range is reported done.
                let status = unsafe {
                    cg_crowd_push_range(
                        crowd as *mut cg_crowd,
                        states as *const cg_entity_state,
                        count,
                    )
                };
                if report.send(status).is_err() {
                    break;
                }
            }
        });
        Helper {
            jobs: Some(jobs),
            done,
            thread: Some(thread),
        }
    }
}

impl Drop for Helper {
    fn drop(&mut self) {
        self.jobs = None;
        if let Some(thread) = self.thread.take() {
            thread.join().expect("the helper thread ends");
        }
    }
}

/// An engine's side of the frame: a crowd created through the C API, the scenario that
/// moves its characters, and the caller's buffers, all allocated before the first frame.
struct Engine {
    crowd: CrowdHandle,
    scenario: Scenario,
    /// The crowd's default axes and unit (+Y up, +Z forward, metres), to place the walkers.
    world: World,
    frame: u32,
    states: Vec<cg_entity_state>,
    gaze: Vec<cg_gaze_info>,
    joints: Vec<cg_quat>,
    eyes: Vec<cg_eye_info>,
    eyelids: Vec<cg_eyelids>,
    /// The second thread of the ranged push, once started.
    helper: Option<Helper>,
}

impl Engine {
    /// A plaza of `characters` walkers in a crowd of `threads` threads (its storage
    /// reordered every 32 steps if `reorder`), after the warm-up.
    fn new(characters: usize, threads: u32, reorder: bool) -> Engine {
        let mut config: cg_crowd_config = init(cg_crowd_config_init);
        config.max_characters = characters as u32;
        config.threads = threads;
        if reorder {
            config.reorder_period = 32;
        }
        let crowd = CrowdHandle::new(&config);
        let scenario = Scenario::plaza(characters, DENSITY, 7);
        let world = CrowdConfig::default().world;
        let mut desc: cg_character_desc = init(cg_character_desc_init);
        let mut state: cg_entity_state = init(cg_entity_state_init);
        state.flags = CG_STATE_HEADING_FROM_MOTION | CG_STATE_HAS_VELOCITY;
        let mut states = vec![state; characters];
        for (person, state) in scenario.people.iter().zip(&mut states) {
            desc.position =
                (world.forward * person.position.x + world.side * person.position.y).into();
            desc.heading = person.heading;
            // SAFETY: a live crowd, a filled desc and a live output pointer.
            ok(
                unsafe { cg_crowd_add_character(crowd.as_mut(), &desc, &mut state.id) },
                "add_character",
            );
        }
        let mut joint_total = 0;
        // SAFETY: a live crowd and output pointer.
        ok(
            unsafe {
                cg_crowd_joint_total(crowd.as_const(), 0, characters as u32, &mut joint_total)
            },
            "joint_total",
        );
        let mut engine = Engine {
            crowd,
            scenario,
            world,
            frame: 0,
            states,
            gaze: vec![cg_gaze_info::default(); characters],
            joints: vec![cg_quat::IDENTITY; joint_total],
            eyes: vec![cg_eye_info::default(); characters],
            eyelids: vec![cg_eyelids::default(); characters],
            helper: None,
        };
        for _ in 0..WARM_UP_FRAMES {
            engine.next_states();
            engine.whole_frame();
        }
        engine
    }

    /// The engine's work before a frame (not timed): moves the walkers 1/30 s and writes
    /// their states into the preallocated array.
    fn next_states(&mut self) {
        self.frame += 1;
        self.scenario.advance(DT);
        let (forward, side) = (self.world.forward, self.world.side);
        for (person, state) in self.scenario.people.iter().zip(&mut self.states) {
            state.position = (forward * person.position.x + side * person.position.y).into();
            state.velocity = (forward * person.velocity.x + side * person.velocity.y).into();
            state.heading = person.heading;
        }
    }

    fn push(&mut self) {
        let time = f64::from(self.frame) * f64::from(DT);
        let (states, count) = (self.states.as_ptr(), self.states.len());
        // SAFETY: a live crowd; `states` holds `count` initialised states of the header's
        // size.
        ok(
            unsafe { cg_crowd_push_frame(self.crowd.as_mut(), time, states, count) },
            "push_frame",
        );
    }

    /// The push in two parts: the second on the helper thread, the first on this one.
    fn push_ranged(&mut self) {
        let time = f64::from(self.frame) * f64::from(DT);
        let helper = self.helper.get_or_insert_with(Helper::new);
        let crowd = self.crowd.as_mut();
        let half = self.states.len() / 2;
        // SAFETY: a live crowd, no other call on it meanwhile.
        ok(unsafe { cg_crowd_begin_push(crowd, time) }, "begin_push");
        let second = &self.states[half..];
        let job = (crowd as usize, second.as_ptr() as usize, second.len());
        helper
            .jobs
            .as_ref()
            .expect("jobs")
            .send(job)
            .expect("helper");
        // SAFETY: a live crowd with a push open; `states` holds `half` initialised states.
        ok(
            unsafe { cg_crowd_push_range(crowd, self.states.as_ptr(), half) },
            "push_range",
        );
        ok(
            helper.done.recv().expect("helper"),
            "push_range on the helper",
        );
        // SAFETY: a live crowd; both ranges have returned.
        ok(unsafe { cg_crowd_end_push(crowd) }, "end_push");
    }

    fn step(&mut self) {
        // SAFETY: a live crowd.
        ok(
            unsafe { cg_crowd_step(self.crowd.as_mut(), black_box(DT)) },
            "step",
        );
    }

    fn read_gaze(&mut self) {
        let mut written = 0;
        let (out, count) = (self.gaze.as_mut_ptr(), self.gaze.len());
        // SAFETY: a live crowd; `out` is valid for `count` writes.
        ok(
            unsafe { cg_crowd_read_gaze(self.crowd.as_const(), out, count, &mut written) },
            "read_gaze",
        );
        black_box(&self.gaze);
    }

    fn read_joints(&mut self) {
        let characters = self.states.len() as u32;
        let (out, len) = (self.joints.as_mut_ptr(), self.joints.len());
        // SAFETY: a live crowd; `out` is valid for `len` writes.
        ok(
            unsafe { cg_crowd_read_joints(self.crowd.as_const(), 0, characters, out, len) },
            "read_joints",
        );
        black_box(&self.joints);
    }

    fn read_eyes(&mut self) {
        let characters = self.states.len() as u32;
        let (out, len) = (self.eyes.as_mut_ptr(), self.eyes.len());
        // SAFETY: a live crowd; `out` is valid for `len` writes.
        ok(
            unsafe { cg_crowd_read_eyes(self.crowd.as_const(), 0, characters, out, len) },
            "read_eyes",
        );
        black_box(&self.eyes);
    }

    fn read_eyelids(&mut self) {
        let characters = self.states.len() as u32;
        let (out, len) = (self.eyelids.as_mut_ptr(), self.eyelids.len());
        // SAFETY: a live crowd; `out` is valid for `len` writes.
        ok(
            unsafe { cg_crowd_read_eyelids(self.crowd.as_const(), 0, characters, out, len) },
            "read_eyelids",
        );
        black_box(&self.eyelids);
    }

    /// The engine's frame: push, step, read everything.
    fn whole_frame(&mut self) {
        self.push();
        self.step();
        self.read_gaze();
        self.read_joints();
        self.read_eyes();
    }

    /// Total time of `timed` over `iterations` frames, each prepared by `untimed`.
    fn frames(
        &mut self,
        iterations: u64,
        mut untimed: impl FnMut(&mut Engine),
        mut timed: impl FnMut(&mut Engine),
    ) -> Duration {
        let mut total = Duration::ZERO;
        for _ in 0..iterations {
            untimed(self);
            let start = Instant::now();
            timed(self);
            total += start.elapsed();
        }
        total
    }
}

/// Bones of the Mixamo skeleton, and joints of its chain (3 spine, neck, head, 2 eyes).
const RIG_BONES: usize = 65;
const RIG_JOINTS: usize = 7;

/// Each character's bone rotations, base pose and joints, converted by one rig.
struct Rigs {
    rig: c_api::rig::Rig,
    bones: Vec<cg_quat>,
    base: Vec<cg_quat>,
    joints: Vec<cg_quat>,
}

impl Rigs {
    fn new(characters: usize) -> Rigs {
        let skeleton = c_api::rig::Skeleton::mixamo();
        assert_eq!(skeleton.names.len(), RIG_BONES);
        let rig = skeleton.rig(1.0);
        let mut bones = Vec::with_capacity(characters * RIG_BONES);
        for character in 0..characters {
            bones.extend(skeleton.animated(character as f32 * 0.37));
        }
        let mut rigs = Rigs {
            rig,
            bones,
            base: vec![cg_quat::IDENTITY; characters * RIG_JOINTS],
            joints: Vec::new(),
        };
        rigs.base_pose();
        // The crowd's joints: each base pose turned a little, as gaze does.
        let turn = glam::Quat::from_rotation_y(0.1);
        rigs.joints = rigs
            .base
            .iter()
            .map(|q| (glam::Quat::from_xyzw(q.x, q.y, q.z, q.w) * turn).into())
            .collect();
        rigs
    }

    fn base_pose(&mut self) {
        let chunks = self.bones.chunks(RIG_BONES);
        for (bones, base) in chunks.zip(self.base.chunks_mut(RIG_JOINTS)) {
            // SAFETY: a live rig; the arrays hold the counts given.
            let status = unsafe {
                cg_rig_base_pose(
                    self.rig.0,
                    bones.as_ptr(),
                    RIG_BONES,
                    base.as_mut_ptr(),
                    RIG_JOINTS,
                )
            };
            ok(status, "cg_rig_base_pose");
        }
    }

    fn write_joints(&mut self) {
        let chunks = self.joints.chunks(RIG_JOINTS);
        for (joints, bones) in chunks.zip(self.bones.chunks_mut(RIG_BONES)) {
            // SAFETY: a live rig; the arrays hold the counts given.
            let status = unsafe {
                cg_rig_write_joints(
                    self.rig.0,
                    joints.as_ptr(),
                    RIG_JOINTS,
                    bones.as_mut_ptr(),
                    RIG_BONES,
                )
            };
            ok(status, "cg_rig_write_joints");
        }
    }
}

/// The crowd sizes: all three for `cargo bench`; 1 000 only when built as a test
/// (`cargo test --benches`: debug assertions on, criterion runs each function once).
fn sizes() -> &'static [usize] {
    let benchmarking = std::env::args().any(|argument| argument == "--bench");
    if cfg!(debug_assertions) || !benchmarking {
        &[1_000]
    } else {
        &[1_000, 10_000, 100_000]
    }
}

fn frame(c: &mut Criterion) {
    let mut group = c.benchmark_group("frame");
    for &characters in sizes() {
        group.throughput(Throughput::Elements(characters as u64));
        for threads in [1, 2] {
            let name = |part: &str| BenchmarkId::new(format!("{part}_{threads}t"), characters);
            let mut engine = Engine::new(characters, threads, false);
            group.bench_function(name("frame"), |b| {
                b.iter_custom(|iterations| {
                    engine.frames(iterations, Engine::next_states, Engine::whole_frame)
                })
            });
            group.bench_function(name("push"), |b| {
                b.iter_custom(|iterations| {
                    engine.frames(iterations, Engine::next_states, Engine::push)
                })
            });
            if threads == 2 {
                group.bench_function(name("push_ranged"), |b| {
                    b.iter_custom(|iterations| {
                        engine.frames(iterations, Engine::next_states, Engine::push_ranged)
                    })
                });
            }
            group.bench_function(name("step"), |b| {
                b.iter_custom(|iterations| {
                    // As in the engine's frame: the previous step's outputs are read, so
                    // the step publishes them for the readers.
                    let untimed = |engine: &mut Engine| {
                        engine.read_gaze();
                        engine.read_joints();
                        engine.read_eyes();
                        engine.next_states();
                        engine.push();
                    };
                    engine.frames(iterations, untimed, Engine::step)
                })
            });
            // The step of a crowd whose outputs nobody reads: it publishes none (the
            // difference with `step` is what publishing costs).
            if threads == 1 {
                group.bench_function(name("step_unread"), |b| {
                    b.iter_custom(|iterations| {
                        let untimed = |engine: &mut Engine| {
                            engine.next_states();
                            engine.push();
                        };
                        engine.frames(iterations, untimed, Engine::step)
                    })
                });
            }
            // As in the engine's frame: the last step followed frames whose outputs were
            // read, and published them.
            engine.next_states();
            engine.whole_frame();
            engine.next_states();
            engine.whole_frame();
            group.bench_function(name("read_gaze"), |b| b.iter(|| engine.read_gaze()));
            group.bench_function(name("read_joints"), |b| b.iter(|| engine.read_joints()));
            group.bench_function(name("read_eyes"), |b| b.iter(|| engine.read_eyes()));
            group.bench_function(name("read_eyelids"), |b| b.iter(|| engine.read_eyelids()));
            drop(engine);

            // Each character's bones through the rig (one thread, whatever the crowd's).
            if threads == 1 {
                let mut rigs = Rigs::new(characters);
                group.bench_function(BenchmarkId::new("rig_base_pose", characters), |b| {
                    b.iter(|| rigs.base_pose())
                });
                group.bench_function(BenchmarkId::new("rig_write_joints", characters), |b| {
                    b.iter(|| rigs.write_joints())
                });
                black_box(&rigs.bones);
            }

            // The same frame with the storage reordered every 32 steps.
            let mut engine = Engine::new(characters, threads, true);
            group.bench_function(name("frame_reorder32"), |b| {
                b.iter_custom(|iterations| {
                    engine.frames(iterations, Engine::next_states, Engine::whole_frame)
                })
            });
            if threads == 1 {
                engine.next_states();
                engine.whole_frame();
                group.bench_function(name("push_reorder32"), |b| {
                    b.iter_custom(|iterations| {
                        engine.frames(iterations, Engine::next_states, Engine::push)
                    })
                });
                group.bench_function(name("read_gaze_reorder32"), |b| {
                    b.iter(|| engine.read_gaze())
                });
                group.bench_function(name("read_joints_reorder32"), |b| {
                    b.iter(|| engine.read_joints())
                });
                group.bench_function(name("read_eyes_reorder32"), |b| {
                    b.iter(|| engine.read_eyes())
                });
            }
        }
    }
    group.finish();
}

criterion_group! {
    name = benches;
    // Set here rather than on the group so that `--warm-up-time`, `--measurement-time` and
    // `--sample-size` on the command line still override them. A frame of 100 000
    // characters takes tens of milliseconds: criterion then samples flat (as many frames
    // in each sample).
    config = Criterion::default()
        .sample_size(10)
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_millis(1500));
    targets = frame
}
criterion_main!(benches);
