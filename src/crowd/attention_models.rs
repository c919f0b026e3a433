//! The saliency model (Paper 3, Kokkinara et al. 2011) and the proximity baseline, one
//! character at a time: steps of the attention job for the characters that use them.

use glam::Vec3;

use super::attention_job::AttentionJob;
use super::model_state::{Look, LookTarget, ModelState};
use super::states::CharacterMut;
use crate::attention::saliency::{saliency, Fixation, FixationChannel, SalientPoint};
use crate::attention::TargetPart;
use crate::scene::ids::{EntityKind, NO_ENTITY};

/// Most points (entity parts) a saliency query considers per frame; beyond, the farthest
/// entities are left out.
pub const MAX_SALIENT_POINTS: usize = 96;

/// The target part a saliency fixation names.
fn part_from(value: u8) -> TargetPart {
    match value {
        1 => TargetPart::Head,
        2 => TargetPart::LeftEye,
        3 => TargetPart::RightEye,
        4 => TargetPart::Chest,
        5 => TargetPart::Torso,
        _ => TargetPart::Whole,
    }
}

impl AttentionJob<'_> {
    /// The saliency model for one character (Kokkinara et al. 2011): gathers the points
    /// (objects, and the five parts of characters) within `d_m`, scores them from the eyes,
    /// and renews the eye and head fixations when they run out or leave their field of view.
    pub(super) fn attend_saliency(&self, character: usize, dt: f32, state: CharacterMut<'_>) {
        let config = self.config.saliency;
        let up = self.config.world.up;
        let entity = self.look.scene.character_entities()[character] as usize;
        let eye = self.look.eye_position(character, state.motion);
        let head_forward = self.look.head_forward(character, state.motion);
        let body_forward = self
            .config
            .world
            .heading_direction(self.look.scene.headings()[entity]);
        let max_distance_squared = self.config.scoring.max_distance.powi(2);
        let centre = self.look.scene.ground_positions()[entity];

        // The nearest entities within d_m — by distance, then id, so that neither the grid's
        // visiting order nor the storage order matters — at most as many as there are points
        // (each gives one or five).
        let mut near = [(0.0f32, 0u32, 0u32); MAX_SALIENT_POINTS];
        let mut near_count = 0;
        let mut farthest = 0;
        let by_distance_then_id =
            |a: &(f32, u32, u32), b: &(f32, u32, u32)| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1));
        self.neighbours
            .grid()
            .for_each_near(centre, |other, ground| {
                let distance_squared = (ground - centre).length_squared();
                let index = other as usize;
                if index == entity
                    || distance_squared > max_distance_squared
                    || self.look.scene.impacts()[index] <= 0.0
                {
                    return;
                }
                let candidate = (distance_squared, self.look.scene.ids()[index], other);
                if near_count < MAX_SALIENT_POINTS {
                    near[near_count] = candidate;
                    near_count += 1;
                } else if by_distance_then_id(&candidate, &near[farthest]).is_lt() {
                    near[farthest] = candidate;
                } else {
                    return;
                }
                if near_count == MAX_SALIENT_POINTS {
                    farthest = (0..MAX_SALIENT_POINTS)
                        .max_by(|&a, &b| by_distance_then_id(&near[a], &near[b]))
                        .unwrap_or(0);
                }
            });
        let near = &mut near[..near_count];
        near.sort_unstable_by(by_distance_then_id);

        let mut points = [SalientPoint {
            entity: NO_ENTITY,
            part: 0,
            position: Vec3::ZERO,
            speed: 0.0,
            turn_rate: 0.0,
            social: false,
        }; MAX_SALIENT_POINTS];
        // Whether each point's entity talks (its score is multiplied by the talking gain).
        let mut talks = [false; MAX_SALIENT_POINTS];
        let mut count = 0;
        'entities: for &(_, id, other) in near.iter() {
            let other = other as usize;
            let speed = self.look.scene.velocities()[other].length();
            let turn_rate = self.look.scene.turn_rates()[other];
            let is_character = self.look.scene.kinds()[other] == EntityKind::Character;
            let parts: &[TargetPart] = if is_character {
                &TargetPart::SOCIAL
            } else {
                &[TargetPart::Whole]
            };
            for &part in parts {
                if count == MAX_SALIENT_POINTS {
                    break 'entities;
                }
                let target = LookTarget { entity: id, part };
                if let Some(position) = self.look.target_point(target) {
                    points[count] = SalientPoint {
                        entity: id,
                        part: part as u8,
                        position,
                        speed,
                        turn_rate,
                        social: is_character,
                    };
                    talks[count] = self.look.scene.talking()[other];
                    count += 1;
                }
            }
        }
        let points = &points[..count];
        let mut in_eye = [0u8; MAX_SALIENT_POINTS];
        let mut in_head = [0u8; MAX_SALIENT_POINTS];
        let mut scores = [0.0f32; MAX_SALIENT_POINTS];
        let (mut eye_count, mut head_count) = (0, 0);
        let talking_gain = self.config.scoring.talking_gain;
        for (index, point) in points.iter().enumerate() {
            let direction = point.position - eye;
            scores[index] = saliency(point, eye, head_forward, &config);
            if talks[index] {
                scores[index] *= talking_gain;
            }
            if config.eye_field.contains(head_forward, up, direction) {
                in_eye[eye_count] = index as u8;
                eye_count += 1;
            }
            if config.head_field.contains(body_forward, up, direction) {
                in_head[head_count] = index as u8;
                head_count += 1;
            }
        }
        let fixation = |index: usize| Fixation {
            entity: points[index].entity,
            part: points[index].part,
        };
        let visible = |channel: &FixationChannel, list: &[u8]| {
            list.iter()
                .any(|&index| fixation(index as usize) == channel.target)
        };
        let random = state.model_random;
        let ModelState::Glance(glance) = state.model else {
            return;
        };
        let look = &mut glance.look;
        let state = &mut glance.saliency;
        let eye_visible = visible(&state.eye, &in_eye[..eye_count]);
        state.eye.update(
            dt,
            config.eye_fixation,
            eye_visible,
            eye_count,
            |i| fixation(in_eye[i] as usize),
            |i| scores[in_eye[i] as usize],
            config.random_pick_probability,
            random,
        );
        let head_visible = visible(&state.head, &in_head[..head_count]);
        state.head.update(
            dt,
            config.head_fixation,
            head_visible,
            head_count,
            |i| fixation(in_head[i] as usize),
            |i| scores[in_head[i] as usize],
            config.random_pick_probability,
            random,
        );
        let look_at = |fixation: Fixation| LookTarget {
            entity: fixation.entity,
            part: part_from(fixation.part),
        };
        *look = Look {
            eye: look_at(state.eye.target),
            head: look_at(state.head.target),
        };
    }

    /// The baseline for one character: the head turns to the nearest character within the
    /// proximity radius in front of it (never an object) — the nearest that talks, if any
    /// does (the Second Life default turns heads preferentially to avatars that talk:
    /// Kokkinara et al. §3.3.1); the eyes glance at preset intervals.
    pub(super) fn attend_baseline(&self, character: usize, dt: f32, state: CharacterMut<'_>) {
        let entity = self.look.scene.character_entities()[character] as usize;
        let centre = self.look.scene.ground_positions()[entity];
        let radius_squared = self.config.baseline.proximity_radius.powi(2);
        let forward = self.look.scene.forwards()[entity];
        // (silent, distance², id) of the best so far: talkers first, then the nearest.
        let mut nearest = (true, f32::INFINITY, NO_ENTITY);
        self.neighbours
            .grid()
            .for_each_near(centre, |other, ground| {
                let other = other as usize;
                let distance_squared = (ground - centre).length_squared();
                if other != entity
                    && forward.dot(ground - centre) >= 0.0
                    && self.look.scene.kinds()[other] == EntityKind::Character
                    && distance_squared <= radius_squared
                {
                    // By silence, distance, then id (whatever order the grid visits them in).
                    let id = self.look.scene.ids()[other];
                    let candidate = (!self.look.scene.talking()[other], distance_squared, id);
                    if candidate < nearest {
                        nearest = candidate;
                    }
                }
            });
        let config = self.config.baseline;
        let ModelState::Glance(glance) = state.model else {
            return;
        };
        glance
            .baseline
            .update(dt, nearest.2, &config, state.model_random);
        let head = if nearest.2 == NO_ENTITY {
            LookTarget::NONE
        } else {
            LookTarget {
                entity: nearest.2,
                part: TargetPart::Head,
            }
        };
        glance.look = Look { eye: head, head };
    }
}
