//! The street model on real trajectories (ETH seq_eth, UCY zara01) against what eye
//! trackers measured on walkers outdoors (docs/street.md). Prints the table of
//! docs/street.md: `cargo test --release --test street -- --nocapture`.

mod support;

use crowdgaze::attention::AttentionModel;
use crowdgaze::crowd::CrowdConfig;
use support::field::{field_stats_of, quiet_walkers, replay, tracks, FieldStats, ETH, ZARA};

/// The statistics of every walker, and of the quieter half (those meeting fewer people per
/// minute than the median: the studies' walkers were on quiet streets).
fn street_stats(file: support::field::SceneFile) -> (FieldStats, FieldStats) {
    let frames = replay(
        &tracks(file),
        CrowdConfig::street(),
        AttentionModel::Street,
        &[],
        0.0..0.0,
        None,
    );
    let config = CrowdConfig::street();
    let (distance, half_angle) = (config.scoring.max_distance, config.street.view_half_angle);
    let quiet = quiet_walkers(&frames, distance, half_angle);
    let all = field_stats_of(&frames, distance, half_angle, &|_| true);
    let quiet = field_stats_of(&frames, distance, half_angle, &|track| {
        quiet.contains(&track)
    });
    for (stats, who) in [(&all, "all"), (&quiet, "quiet half")] {
        println!(
        "{} ({who}): {} approaching walkers; fixated at least once {:.1} %, a second time {:.1} %; \
         latency {:.2} s; distance {:.1} m (walkers coming into view from 16 m: {:.1} m, {} \
         of them); duration {:.2} s; walking time on walkers {:.1} % ({:.1} % for those \
         meeting fewer people, {:.1} % more); fixated while in view: {:.1} % within 3 m, \
         {:.1} % at 5-15 m",
        file.name,
        stats.approaching,
        100.0 * stats.fixated_once,
        100.0 * stats.fixated_twice,
        stats.latency,
        stats.distance,
        stats.distance_far,
        stats.far_count,
        stats.duration,
        100.0 * stats.time_share,
        100.0 * stats.time_share_by_met.0,
        100.0 * stats.time_share_by_met.1,
        100.0 * stats.civil.0,
        100.0 * stats.civil.1,
    );
    }
    (all, quiet)
}

#[test]
fn walkers_on_real_trajectories_look_as_eye_trackers_measured() {
    let all: Vec<_> = [ETH, ZARA].map(|file| (file, street_stats(file))).into();
    for (file, (every, stats)) in all {
        assert!(stats.approaching > 150, "{}", stats.approaching);
        // 73–86 % of approaching pedestrians fixated at least once.
        assert!(
            (0.70..=0.88).contains(&stats.fixated_once),
            "{}: fixated once {}",
            file.name,
            stats.fixated_once
        );
        // About 30 % fixated a second time.
        assert!(
            (0.2..=0.4).contains(&stats.fixated_twice),
            "{}: twice {}",
            file.name,
            stats.fixated_twice
        );
        // 0.55–0.75 s from coming into view to the first fixation.
        assert!(
            (0.5..=0.85).contains(&stats.latency),
            "{}: latency {}",
            file.name,
            stats.latency
        );
        // About 0.5 s per fixation.
        assert!(
            (0.4..=0.6).contains(&stats.duration),
            "{}: duration {}",
            file.name,
            stats.duration
        );
        // About 15 m away, where the view allows it: walkers coming into view from its
        // edge (few of them in the small zara01 scene).
        if every.far_count >= 20 {
            assert!(
                (12.5..=17.0).contains(&every.distance_far),
                "{}: far distance {}",
                file.name,
                every.distance_far
            );
        }
        // About 14 % of walking time on others, more for those who meet more people.
        assert!(
            (0.08..=0.22).contains(&stats.time_share),
            "{}: time share {}",
            file.name,
            stats.time_share
        );
        assert!(
            stats.time_share_by_met.1 > stats.time_share_by_met.0,
            "{}: {:?}",
            file.name,
            stats.time_share_by_met
        );
        // Civil inattention: less looking at strangers within 3 m than at 5–15 m.
        assert!(
            stats.civil.0 < 0.6 * stats.civil.1,
            "{}: {:?}",
            file.name,
            stats.civil
        );
    }
}
