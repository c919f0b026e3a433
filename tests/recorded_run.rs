//! A recorded run: the real ETH trajectories (`seq_eth`) through a crowd mixing the three
//! attention models and every chain shape (`support::varied_chains`, base poses on every
//! third person), 1 200 steps at 30 fps, people added at their first sample and removed
//! after their last. Every step's outputs (gaze, eyes and joints of every character, as bits)
//! are hashed, and the hashes must equal `tests/data/recorded_run.txt`, recorded before a
//! change that must not change behaviour (a refactoring): a change of one bit anywhere fails.
//!
//! Rewrite the recording with `CG_BLESS=1 cargo test --test recorded_run` only when a change
//! of behaviour is intended, and say so in the commit.

mod support;

use crowdgaze::attention::{AttentionModel, CharacterParams};
use crowdgaze::scene::EntityUpdate;
use crowdgaze::{Axis, CharacterDesc, Crowd, CrowdConfig, World};
use glam::Vec3;
use std::collections::BTreeMap;
use std::path::Path;

/// ETH sample frames to run (one sample every 0.4 s; 12 steps of 1/30 s each).
const SAMPLES: usize = 100;
const STEPS_PER_SAMPLE: usize = 12;

/// Person `p` runs `MODELS[p % 3]`.
const MODELS: [AttentionModel; 3] = [
    AttentionModel::Crowd,
    AttentionModel::Saliency,
    AttentionModel::Baseline,
];

/// FNV-1a over the words' bytes.
fn hash(words: &[u32]) -> u64 {
    let mut hash = 0xcbf2_9ce4_8422_2325_u64;
    for word in words {
        for byte in word.to_le_bytes() {
            hash ^= u64::from(byte);
            hash = hash.wrapping_mul(0x0000_0100_0000_01b3);
        }
    }
    hash
}

/// One line per step: the step's index, its character count and the hash of its outputs.
fn run() -> Vec<String> {
    let rows = support::read_trajectories(support::ETH_SEQ_ETH);
    let mut frames: Vec<u32> = rows.iter().map(|row| row.0).collect();
    frames.dedup();
    let frames = &frames[..SAMPLES];
    let mut last_frame = BTreeMap::new();
    for &(frame, person, _, _) in &rows {
        last_frame.insert(person, frame);
    }

    // ETH's ground plane is (x, y): Z up, walking along +X.
    let world = World::new(Axis::PositiveZ, Axis::PositiveX, 1.0).unwrap();
    let mut crowd = Crowd::new(CrowdConfig {
        world,
        max_characters: 400,
        seed: 11,
        ..CrowdConfig::default()
    })
    .unwrap();
    // Every chain shape side by side, and base poses on every third person.
    let chains = support::varied_chains(&world);
    let mut ids: BTreeMap<u32, u32> = BTreeMap::new();
    let mut lines = Vec::new();
    let mut step = 0;
    for &frame in frames {
        let mut updates = Vec::new();
        for &(_, person, x, y) in rows.iter().filter(|row| row.0 == frame) {
            let position = Vec3::new(x, y, 0.0);
            let id = match ids.get(&person) {
                Some(&id) => id,
                None => {
                    let desc = CharacterDesc {
                        position,
                        chain: Some(chains[person as usize % chains.len()]),
                        ..Default::default()
                    };
                    let id = crowd.add_character(&desc).unwrap();
                    if person % 3 == 1 {
                        support::bend(&mut crowd, id, person as usize);
                    }
                    let params = crowd.character_params(id).unwrap();
                    let model = MODELS[person as usize % MODELS.len()];
                    crowd
                        .set_character_params(id, &CharacterParams { model, ..params })
                        .unwrap();
                    ids.insert(person, id);
                    id
                }
            };
            updates.push(EntityUpdate {
                id,
                position,
                heading: 0.0,
                heading_from_motion: true,
                velocity: None,
                talking: false,
            });
        }
        crowd.push_frame(f64::from(frame) / 15.0, &updates).unwrap();
        for _ in 0..STEPS_PER_SAMPLE {
            crowd.step(1.0 / 30.0).unwrap();
            let bits = support::output_bits(&crowd);
            lines.push(format!(
                "{step} {} {:016x}",
                crowd.character_count(),
                hash(&bits)
            ));
            step += 1;
        }
        // People whose track ended leave the crowd.
        ids.retain(|person, id| {
            let stays = last_frame[person] > frame;
            if !stays {
                crowd.remove_entity(*id).unwrap();
            }
            stays
        });
    }
    lines
}

#[test]
#[cfg_attr(miri, ignore)]
fn the_eth_run_matches_its_recording() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/recorded_run.txt");
    let lines = run();
    assert_eq!(lines.len(), SAMPLES * STEPS_PER_SAMPLE);
    let people: usize = lines
        .iter()
        .map(|line| line.split(' ').nth(1).unwrap().parse::<usize>().unwrap())
        .max()
        .unwrap();
    assert!(people >= 10, "too few people to mean anything: {people}");
    let text = lines.join("\n") + "\n";
    if std::env::var_os("CG_BLESS").is_some() {
        std::fs::create_dir_all(path.parent().unwrap()).unwrap();
        std::fs::write(&path, &text).unwrap();
        return;
    }
    let recorded = std::fs::read_to_string(&path)
        .unwrap_or_else(|e| panic!("{}: {e} (record it with CG_BLESS=1)", path.display()));
    for (step, (now, then)) in lines.iter().zip(recorded.lines()).enumerate() {
        assert_eq!(now, then, "step {step} differs from the recording");
    }
    assert_eq!(
        lines.len(),
        recorded.lines().count(),
        "the recording's length"
    );
}
