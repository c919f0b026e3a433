//! The conversation model against its sources: over 10 simulated minutes of seeded
//! turn-taking in groups of two and three, the shares of listener → speaker, speaker →
//! listener and mutual gaze, and the mean lengths of glances and mutual glances.

use super::*;

const DT: f32 = 1.0 / 30.0;
const FRAMES: usize = 10 * 60 * 30;

/// Who talks each frame: turns of 4–16 s by a random member (not the last one), with pauses
/// of 0–1 s between them.
fn turns(members: usize, seed: u64) -> Vec<[bool; MAX_MEMBERS]> {
    let mut random = Random::new(seed);
    let mut frames = Vec::with_capacity(FRAMES);
    let mut last = usize::MAX;
    while frames.len() < FRAMES {
        let mut speaker = random.below(members as u32) as usize;
        if speaker == last {
            speaker = (speaker + 1) % members;
        }
        last = speaker;
        let mut talking = [false; MAX_MEMBERS];
        talking[speaker] = true;
        let turn = (random.range(4.0, 16.0) / DT) as usize;
        let pause = (random.range(0.0, 1.0) / DT) as usize;
        frames.extend(std::iter::repeat_n(talking, turn));
        frames.extend(std::iter::repeat_n([false; MAX_MEMBERS], pause));
    }
    frames.truncate(FRAMES);
    frames
}

/// Measured over a run: shares and mean glance lengths.
#[derive(Debug)]
struct Measured {
    listener_share: f32,
    speaker_share: f32,
    mutual_share: f32,
    glance: f32,
    mutual_glance: f32,
}

fn measure(members: usize, seed: u64) -> Measured {
    let settings = ConversationSettings::default();
    let ids: Vec<u32> = (0..members as u32).map(|i| 100 + i).collect();
    let mut conversation = Conversation::new(&ids);
    let (mut listening, mut listener_at) = (0usize, 0usize);
    let (mut speaking, mut speaker_at) = (0usize, 0usize);
    let mut mutual = 0usize;
    // Run lengths (frames) of each member's glance at one member, and of each pair's
    // mutual gaze.
    let mut glance_run = vec![(AWAY, 0usize); members];
    let mut glances = Vec::new();
    let mut mutual_run = vec![vec![0usize; members]; members];
    let mut mutual_glances = Vec::new();
    for talking in turns(members, seed) {
        conversation.advance(&settings, 7, DT, &talking);
        let target = |m: usize| conversation.gaze[m].target;
        let speaker = conversation.speaker;
        for m in 0..members {
            if talking[m] {
                speaking += 1;
                if target(m) != AWAY {
                    speaker_at += 1;
                    let listener = usize::from(target(m));
                    if target(listener) == m as u8 {
                        mutual += 1;
                    }
                }
            } else if speaker != NOBODY {
                listening += 1;
                listener_at += usize::from(target(m) == speaker);
            }
            let (looked, length) = glance_run[m];
            if target(m) == looked && looked != AWAY {
                glance_run[m].1 += 1;
            } else {
                if looked != AWAY && length > 0 {
                    glances.push(length);
                }
                glance_run[m] = (target(m), usize::from(target(m) != AWAY));
            }
            for (other, run) in mutual_run[m].iter_mut().enumerate().skip(m + 1) {
                let both = target(m) == other as u8 && target(other) == m as u8;
                if both {
                    *run += 1;
                } else if *run > 0 {
                    mutual_glances.push(*run);
                    *run = 0;
                }
            }
        }
    }
    let mean = |runs: &[usize]| runs.iter().sum::<usize>() as f32 / runs.len() as f32 * DT;
    Measured {
        listener_share: listener_at as f32 / listening as f32,
        speaker_share: speaker_at as f32 / speaking as f32,
        mutual_share: mutual as f32 / speaking as f32,
        glance: mean(&glances),
        mutual_glance: mean(&mutual_glances),
    }
}

#[test]
fn groups_of_two_and_three_look_as_argyle_measured() {
    for members in [2, 3] {
        for seed in [1, 2] {
            let m = measure(members, seed);
            println!("{members} members, seed {seed}: {m:?}");
            let within = |value: f32, target: f32, what: &str| {
                assert!(
                    (value - target).abs() <= 0.10,
                    "{members} members, seed {seed}: {what} {value}, target {target}"
                );
            };
            within(m.listener_share, 0.75, "listener → speaker");
            within(m.speaker_share, 0.41, "speaker → listener");
            within(m.mutual_share, 0.31, "mutual");
            let close = |value: f32, target: f32, what: &str| {
                assert!(
                    (value - target).abs() <= 0.3 * target,
                    "{members} members, seed {seed}: {what} {value} s, target {target} s"
                );
            };
            close(m.glance, 3.0, "mean glance");
            close(m.mutual_glance, 1.2, "mean mutual glance");
        }
    }
}

#[test]
fn a_new_speaker_looks_away_first_and_listeners_follow_the_speaker() {
    let settings = ConversationSettings::default();
    let mut conversation = Conversation::new(&[1, 2, 3]);
    let mut talking = [false; MAX_MEMBERS];
    talking[1] = true;
    conversation.advance(&settings, 7, DT, &talking);
    assert_eq!(conversation.speaker, 1);
    assert_eq!(conversation.gaze[1].target, AWAY);
    // Away for the whole aversion, then at a listener at some point of the turn.
    let mut looked = false;
    for frame in 1..300 {
        conversation.advance(&settings, 7, DT, &talking);
        let target = conversation.gaze[1].target;
        if (frame as f32) * DT < settings.turn_start_aversion - 0.01 {
            assert_eq!(target, AWAY, "frame {frame}");
        }
        looked |= target == 0 || target == 2;
        // Listeners look at the speaker or away, never at each other.
        for listener in [0, 2] {
            let target = conversation.gaze[listener].target;
            assert!(target == 1 || target == AWAY, "{target}");
        }
    }
    assert!(looked);
    // With no aversion the new speaker may look at a listener at once.
    let settings = ConversationSettings {
        turn_start_aversion: 0.0,
        ..settings
    };
    let starts_at_someone = (0..200u32)
        .filter(|&seed| {
            let mut conversation = Conversation::new(&[1, 2]);
            conversation.advance(&settings, u64::from(seed), DT, &talking);
            conversation.gaze[1].target != AWAY
        })
        .count();
    assert!(
        (40..=130).contains(&starts_at_someone),
        "{starts_at_someone}"
    );
}

#[test]
fn removing_a_member_keeps_the_others_gaze_consistent() {
    let settings = ConversationSettings::default();
    let mut conversation = Conversation::new(&[10, 20, 30, 40]);
    let mut talking = [false; MAX_MEMBERS];
    talking[3] = true;
    for _ in 0..200 {
        conversation.advance(&settings, 3, DT, &talking);
    }
    // Member 1 (id 20) leaves: the last one, the speaker (id 40), moves into its place.
    let moved = conversation.remove(1);
    assert_eq!(moved, Some(40));
    assert_eq!(conversation.member_ids(), &[10, 40, 30]);
    assert_eq!(conversation.speaker, 1, "the speaker follows its move");
    for gaze in &conversation.gaze[..3] {
        assert!(gaze.target == AWAY || usize::from(gaze.target) < 3);
    }
    // Removing the speaker leaves the group without one until someone talks.
    conversation.remove(1);
    assert_eq!(conversation.speaker, NOBODY);
    conversation.advance(&settings, 3, DT, &[false; MAX_MEMBERS]);
    for gaze in &conversation.gaze[..2] {
        assert!(gaze.target == AWAY || usize::from(gaze.target) < 2);
    }
}

#[test]
fn settings_out_of_range_are_refused() {
    let good = ConversationSettings::default();
    assert!(good.validate().is_ok());
    for bad in [
        ConversationSettings {
            listener_share: 1.0,
            ..good
        },
        ConversationSettings {
            speaker_share: 0.0,
            ..good
        },
        ConversationSettings {
            idle_glance: 0.0,
            ..good
        },
        ConversationSettings {
            turn_start_aversion: -1.0,
            ..good
        },
    ] {
        assert!(
            matches!(bad.validate(), Err(Error::InvalidArgument(_))),
            "{bad:?}"
        );
    }
    let nan = ConversationSettings {
        speaker_glance: f32::NAN,
        ..good
    };
    assert!(matches!(nan.validate(), Err(Error::NonFinite(_))));
}

#[test]
fn a_long_step_starts_glances_afresh_and_normal_frames_go_on() {
    let settings = ConversationSettings::default();
    let mut talking = [false; MAX_MEMBERS];
    talking[0] = true;
    for dt in [100.0, 1.0e7, 3.0e8, f32::MAX] {
        let mut conversation = Conversation::new(&[100, 101, 102]);
        for _ in 0..30 {
            conversation.advance(&settings, 7, DT, &talking);
        }
        conversation.advance(&settings, 7, dt, &talking);
        for member in 0..3 {
            let left = conversation.gaze[member].left;
            assert!(
                left > 0.0 && left.is_finite(),
                "dt {dt}: glance left {left}"
            );
        }
        // Normal frames then change glances at the usual pace (seconds), not every frame.
        let draws = |c: &Conversation| c.gaze[..3].iter().map(|g| g.draws).sum::<u32>();
        let before = draws(&conversation);
        for _ in 0..30 {
            conversation.advance(&settings, 7, DT, &talking);
        }
        assert!(
            draws(&conversation) - before < 10,
            "dt {dt}: glances every frame"
        );
    }
}
