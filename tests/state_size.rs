//! Per-character state (design §10: at most 1 KiB per character). The size of every type
//! `Crowd::state_bytes_per_character` adds up, and the total, so that growth is noticed.
//! Update the numbers here (and the sum) when a type changes on purpose.

use std::mem::size_of;

use crowdgaze::attention::baseline::BaselineState;
use crowdgaze::attention::candidates::NeighbourIndex;
use crowdgaze::attention::following::FollowState;
use crowdgaze::attention::interest::InterestTracker;
use crowdgaze::attention::quantile::ScoreHistogram;
use crowdgaze::attention::saliency::FixationChannel;
use crowdgaze::attention::street::StreetState;
use crowdgaze::attention::CharacterParams;
use crowdgaze::crowd::{ExplicitTarget, GlanceState, Look, ModelState, TargetPriority};
use crowdgaze::ik::{BlinkState, GazeMotion, MAX_CHAIN_JOINTS};
use crowdgaze::math::packed::PackedQuat;
use crowdgaze::math::random::Random;
use crowdgaze::scene::Scene;
use crowdgaze::Crowd;

#[test]
fn every_per_character_type_has_its_recorded_size() {
    assert_eq!(size_of::<CharacterParams>(), 24);
    // A score histogram (64 16-bit counts, their total and the quantile cursor's bin and
    // count below it) and 20 four-byte fields.
    assert_eq!(size_of::<ScoreHistogram>(), 140);
    assert_eq!(size_of::<InterestTracker>(), 216);
    // The crowd's base pose of each chain joint.
    assert_eq!(size_of::<[PackedQuat; MAX_CHAIN_JOINTS]>(), 120);
    // Deltas (240), packed start pose (120), eye rays (48), last targets (24), target key
    // (8), four times (16), four one-byte fields, 4 bytes of padding.
    assert_eq!(size_of::<GazeMotion>(), 464);
    assert_eq!(size_of::<Random>(), 8);
    // An explicit target and its priority are stored in 16 bytes (the tag's word holds
    // the priority), not as this pair.
    assert_eq!(size_of::<Option<(ExplicitTarget, TargetPriority)>>(), 20);
    // Blinks: a clock and the count of draws.
    assert_eq!(size_of::<BlinkState>(), 8);
    assert_eq!(size_of::<Look>(), 16);
    // The crowd's saliency state: one channel for the eyes, one for the head.
    assert_eq!(size_of::<FixationChannel>(), 20);
    assert_eq!(size_of::<BaselineState>(), 20);
    // A character keeps the state of its own attention model only: the tracker (216) or
    // the look, saliency and baseline state (76), and a tag.
    assert_eq!(size_of::<GlanceState>(), 76);
    assert_eq!(size_of::<ModelState>(), 220);
    // The street model's walkers in view (10 × 20 bytes) and fixation: within the
    // tracker's size, so a character's model state does not grow.
    assert!(size_of::<StreetState>() <= size_of::<InterestTracker>());
    // Gaze following: the point glanced at (12), the reaction time and the glance's time
    // left, the lookers' weight already decided on, the time since a looker was last
    // seen, glances so far.
    assert_eq!(size_of::<FollowState>(), 32);
    // Each entity's share of the scene and of the neighbour index.
    assert_eq!(Scene::bytes_per_entity(), 78);
    assert_eq!(NeighbourIndex::bytes_per_entity(), 52);
}

#[test]
fn state_per_character_adds_up() {
    // 24 parameters + 4 chain index + 120 packed base pose + 1 posed flag + 16 explicit
    // target + 4 place in a conversation + 4 place in the readers' order + 220 attention
    // model state + 464 gaze motion + 2 × 8 random streams + 8 level of detail + 8 blinks
    // + 32 gaze following, + 78 scene + 52 neighbour index, + 4 visiting order + 1 (three
    // bits of scratch, rounded up).
    assert_eq!(Crowd::state_bytes_per_character(), 1056);
    // The design's budget was 1 KiB; gaze following (issue #39) adds its 32 bytes on
    // purpose (docs/street.md says why), and a crowd with following on reserves one cue
    // (48 bytes) per character, filled as a step begins by those who stare or glance.
    assert!(Crowd::state_bytes_per_character() <= 1024 + size_of::<FollowState>());
    assert_eq!(size_of::<crowdgaze::attention::following::Cue>(), 48);
}

#[test]
fn outputs_kept_for_the_readers_add_up() {
    // 44 gaze info + 4 where the joints start + 4 reader position of each storage index
    // (the final joint rotations, 16 bytes a joint, are reserved as characters are added).
    assert_eq!(size_of::<crowdgaze::GazeInfo>(), 44);
    assert_eq!(Crowd::output_bytes_per_character(), 52);
}
