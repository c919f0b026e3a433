//! What the readers report for one character, computed from its state: where it looks
//! ([`GazeInfo`]) and its chain's final joint rotations. The readers compute them on
//! demand; the gaze job computes them for each character it has moved and publishes them in
//! the readers' order ([`super::published`]) — the same functions, so the same bits.

use glam::Quat;

use super::look::LookContext;
use super::states::CharacterView;
use super::values::GazeInfo;
use crate::attention::AttentionModel;
use crate::scene::ids::NO_ENTITY;

/// Where the character at storage index `character`, whose state is `view`, looks now.
/// `initial_threshold` is the crowd's starting interest threshold (what characters of the
/// saliency and baseline models report).
pub(super) fn gaze_info(
    look: &LookContext<'_>,
    initial_threshold: f32,
    character: usize,
    view: CharacterView<'_>,
) -> GazeInfo {
    let scene = look.scene;
    let entity = scene.character_entities()[character] as usize;
    let tracker = view.model.tracker();
    let (target, s_max, threshold, attentive_fraction, interest_count) = match look.plan {
        Some(plan) => {
            let (target, s_max, threshold) = plan.current(character);
            let count = plan.constraints(character).len() as u32;
            (
                target,
                s_max,
                threshold,
                plan.attentive_fraction(character),
                count,
            )
        }
        None => match tracker {
            Some(tracker) => {
                let (attentive, observed) = tracker.attentive_seconds();
                let fraction = if observed > 0.0 {
                    attentive / observed
                } else {
                    0.0
                };
                (
                    tracker.interest(),
                    tracker.s_max(),
                    tracker.threshold(),
                    fraction,
                    tracker.interest_count(),
                )
            }
            // Characters of the other models report what a fresh tracker would: no
            // interest point, the initial threshold; the street model counts its fixations.
            None => (
                NO_ENTITY,
                0.0,
                initial_threshold,
                0.0,
                view.model
                    .street()
                    .map_or(0, |street| street.fixation_count()),
            ),
        },
    };
    let current = look.current_look(character, view);
    let target_position = match look.gaze_request(character, view) {
        Some(request) => request.eye_target,
        None => {
            let ahead = look.world.heading_direction(scene.headings()[entity]);
            scene.look_at_point(entity) + ahead * 10.0
        }
    };
    let exists = |id: u32| scene.index_of(id).is_some();
    let known = |id: u32| if exists(id) { id } else { NO_ENTITY };
    let attending = match look.characters.params[character].model {
        AttentionModel::Crowd => exists(target),
        _ => exists(current.eye.entity) || exists(current.head.entity),
    };
    GazeInfo {
        character: scene.ids()[entity],
        target: known(current.eye.entity),
        target_part: current.eye.part,
        head_target: known(current.head.entity),
        target_position,
        s_max,
        // The trackers and the plan use +inf for "never"; callers get a finite value.
        threshold: threshold.min(f32::MAX),
        attending,
        attentive_fraction,
        interest_count,
    }
}

/// Writes the chain joints of the character at storage index `character`, whose state is
/// `view`, to the start of `out` (which holds them all), bottom to top: the final local
/// rotations `base * delta`, or the deltas alone with `deltas_only`. Returns how many.
pub(super) fn joint_rotations(
    look: &LookContext<'_>,
    character: usize,
    view: CharacterView<'_>,
    deltas_only: bool,
    out: &mut [Quat],
) -> usize {
    let deltas = view.motion.deltas();
    let base = look.characters.base_pose(look.chains, character);
    for ((slot, delta), base) in out.iter_mut().zip(deltas).zip(&base) {
        *slot = if deltas_only { *delta } else { *base * *delta };
    }
    deltas.len()
}
