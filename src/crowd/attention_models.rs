//! The saliency model (Paper 3, Kokkinara et al. 2011), the proximity baseline and the
//! street model, one character at a time, and gaze following for every model: steps of
//! the attention job for the characters that use them.

use glam::Vec3;

use super::attention_job::AttentionJob;
use super::model_state::{Look, LookTarget, ModelState};
use super::states::CharacterMut;
use super::values::TargetPriority;
use crate::attention::following::{Cue, CueRuns, FollowState, CUE_CELL_MIN};
use crate::attention::saliency::{saliency, Fixation, FixationChannel, SalientPoint};
use crate::attention::street::{Noticed, STREET_MEMORY};
use crate::attention::TargetPart;
use crate::math::random::Random;
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

/// Gaze-following weights are summed in these fixed-point units, so that the sum does not
/// depend on the order the neighbours are visited in (storage order, threads).
const WEIGHT_UNITS: f32 = 4096.0;

impl AttentionJob<'_> {
    /// The street model for one character: the walkers (characters) in view — within
    /// `max_distance` and the street view's half-angle about the walking direction —
    /// nearest first, then its fixation update ([`StreetState::update`]).
    pub(super) fn attend_street(&self, character: usize, dt: f32, state: CharacterMut<'_>) {
        let scene = self.look.scene;
        let entity = scene.character_entities()[character] as usize;
        let centre = scene.ground_positions()[entity];
        let velocity = scene.velocities()[entity];
        // The walking direction; the body's heading when standing.
        let direction = if velocity.length_squared() > 0.04 {
            velocity.normalize()
        } else {
            scene.forwards()[entity]
        };
        let street = &self.config.street;
        let cos_half = street.view_half_angle.cos();
        let max_distance_squared = self.config.scoring.max_distance.powi(2);
        // The nearest STREET_MEMORY walkers in view as (distance², id), kept sorted.
        let mut nearest = [(f32::INFINITY, NO_ENTITY); STREET_MEMORY];
        self.neighbours
            .grid()
            .for_each_near(centre, |other, ground| {
                let other = other as usize;
                let offset = ground - centre;
                let distance_squared = offset.length_squared();
                if other == entity
                    || distance_squared > max_distance_squared
                    || scene.kinds()[other] != EntityKind::Character
                    || scene.impacts()[other] <= 0.0
                    || direction.dot(offset) < cos_half * distance_squared.sqrt()
                {
                    return;
                }
                let candidate = (distance_squared, scene.ids()[other]);
                let last = STREET_MEMORY - 1;
                if by_distance_then_id(&candidate, &nearest[last]).is_lt() {
                    nearest[last] = candidate;
                    let mut at = last;
                    while at > 0 && by_distance_then_id(&nearest[at], &nearest[at - 1]).is_lt() {
                        nearest.swap(at, at - 1);
                        at -= 1;
                    }
                }
            });
        let mut noticed = [Noticed {
            entity: NO_ENTITY,
            distance: 0.0,
        }; STREET_MEMORY];
        let mut count = 0;
        for &(distance_squared, id) in nearest.iter().take_while(|n| n.1 != NO_ENTITY) {
            noticed[count] = Noticed {
                entity: id,
                distance: distance_squared.sqrt(),
            };
            count += 1;
        }
        if let ModelState::Street(walkers) = state.model {
            walkers.update(dt, &noticed[..count], street, state.model_random);
        }
    }

    /// Gaze following for one character ([`FollowState::update`]): the lookers in its
    /// view within the follow distance — the characters whose [`Cue`] this step shows
    /// them looking at a point, found by ground cell — weighed by how they walk relative
    /// to it, and the point the nearest looks at. A character
    /// that game logic makes look somewhere (an overriding target) does not follow.
    pub(super) fn follow(
        &self,
        character: usize,
        dt: f32,
        follow: &mut FollowState,
        random: &mut Random,
        runs: &mut CueRuns,
    ) {
        if matches!(
            self.look.characters.explicit[character].get(),
            Some((_, TargetPriority::Override))
        ) {
            return;
        }
        let config = &self.config.following;
        let scene = self.look.scene;
        let entity = scene.character_entities()[character] as usize;
        let own_id = scene.ids()[entity];
        let centre = scene.ground_positions()[entity];
        let forward = scene.forwards()[entity];
        let cos_half = config.view_half_angle.cos();
        let max_distance_squared = config.distance * config.distance;
        let oncoming_units = (config.oncoming_weight * WEIGHT_UNITS).round() as u64;
        let mut total_units = 0u64;
        // (distance², id, point) of the nearest looker.
        let mut nearest = (f32::INFINITY, NO_ENTITY, Vec3::ZERO);
        // The lookers within the follow distance are in this cell's row and the rows
        // beside it, each three cells wide: three runs of the cell-sorted cues.
        let cues = self.look.cues;
        let cell_size = config.distance.max(CUE_CELL_MIN);
        let cell = Cue::coordinates(centre, cell_size);
        for run in runs.around(cell, cues) {
            for cue in &cues[run] {
                let offset = cue.ground - centre;
                let distance_squared = offset.length_squared();
                if cue.id == own_id
                    || distance_squared > max_distance_squared
                    || forward.dot(offset) < cos_half * distance_squared.sqrt()
                {
                    continue;
                }
                // Walking towards the character (within 60° of straight at it).
                let speed = cue.velocity.length();
                let oncoming = speed > 0.3
                    && cue.velocity.dot(-offset) > 0.5 * speed * distance_squared.sqrt();
                let units = (cue.weight * WEIGHT_UNITS).round() as u64;
                total_units += if oncoming {
                    units * oncoming_units / WEIGHT_UNITS as u64
                } else {
                    units
                };
                if (distance_squared, cue.id) < (nearest.0, nearest.1) {
                    nearest = (distance_squared, cue.id, cue.point);
                }
            }
        }
        let lookers = total_units as f32 / WEIGHT_UNITS;
        follow.update(dt, lookers, nearest.2, config, random);
    }
}

/// Orders (distance², id) pairs by distance, then id.
fn by_distance_then_id(a: &(f32, u32), b: &(f32, u32)) -> std::cmp::Ordering {
    a.0.total_cmp(&b.0).then(a.1.cmp(&b.1))
}
