//! The crowd's glue for the saliency and baseline attention models: where the parts of a
//! character are, what each character's eyes and head are fixating, and the viewer entity.

use glam::{Quat, Vec3};

use super::states::{CharacterMut, CharacterView};
use super::{Crowd, ExplicitTarget, Shared, TargetPriority};
use crate::attention::baseline::BaselineState;
use crate::attention::interest::{InterestConfig, InterestTracker};
use crate::attention::saliency::{saliency, Fixation, FixationChannel, SalientPoint};
use crate::attention::{AttentionModel, TargetPart};
use crate::error::{ensure_all_finite, Error, Result};
use crate::ik::{GazeChain, GazeMotion, GazeRequest, JointRole, MotionStyle};
use crate::scene::ids::{EntityKind, NO_ENTITY};

/// Most points (entity parts) a saliency query considers per frame; beyond, the farthest
/// entities are left out.
pub const MAX_SALIENT_POINTS: usize = 96;

/// One of the things a character looks at: an entity and which part of it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct LookTarget {
    /// Entity id, or `NO_ENTITY`.
    pub entity: u32,
    /// The part of the entity.
    pub part: TargetPart,
}

impl LookTarget {
    /// Nothing.
    pub const NONE: LookTarget = LookTarget {
        entity: NO_ENTITY,
        part: TargetPart::Whole,
    };
}

/// Where the saliency or baseline model wants a character's eyes and head.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Look {
    /// The eyes' target.
    pub eye: LookTarget,
    /// The head's (and body's) target.
    pub head: LookTarget,
}

impl Look {
    /// Looking ahead.
    pub const NONE: Look = Look {
        eye: LookTarget::NONE,
        head: LookTarget::NONE,
    };

    /// Drops every reference to a removed entity.
    pub fn forget(&mut self, id: u32) {
        if self.eye.entity == id {
            self.eye = LookTarget::NONE;
        }
        if self.head.entity == id {
            self.head = LookTarget::NONE;
        }
    }
}

/// A character's saliency fixations: one channel for the eyes, one for the head.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct SaliencyState {
    /// The eyes' fixation.
    pub eye: FixationChannel,
    /// The head's fixation.
    pub head: FixationChannel,
}

/// The saliency and baseline models' state of a character: where they want its eyes and
/// head, the saliency fixations and the baseline's glances.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GlanceState {
    /// Where the model wants the eyes and head.
    pub look: Look,
    /// Saliency fixations.
    pub saliency: SaliencyState,
    /// Baseline glances.
    pub baseline: BaselineState,
}

/// What a character's attention model keeps between frames. Only the model the character
/// uses has state (a character carries the larger of the two, not both): switching to or
/// from the crowd model starts the new model afresh; the saliency and baseline models
/// share theirs.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ModelState {
    /// The crowd model's online interest tracker.
    Crowd(InterestTracker),
    /// The saliency or baseline model's state.
    Glance(GlanceState),
}

impl ModelState {
    /// A fresh state for `model` (`attention_fraction` and `interest` set up the crowd
    /// model's tracker).
    pub fn new(model: AttentionModel, attention_fraction: f32, interest: &InterestConfig) -> Self {
        match model {
            AttentionModel::Crowd => {
                ModelState::Crowd(InterestTracker::new(attention_fraction, interest))
            }
            AttentionModel::Saliency | AttentionModel::Baseline => {
                ModelState::Glance(GlanceState {
                    look: Look::NONE,
                    saliency: SaliencyState::default(),
                    baseline: BaselineState::default(),
                })
            }
        }
    }

    /// True if this is the state `model` keeps.
    pub fn serves(&self, model: AttentionModel) -> bool {
        matches!(
            (self, model),
            (ModelState::Crowd(_), AttentionModel::Crowd)
                | (
                    ModelState::Glance(_),
                    AttentionModel::Saliency | AttentionModel::Baseline
                )
        )
    }

    /// The crowd model's tracker, if this is its state.
    pub fn tracker(&self) -> Option<&InterestTracker> {
        match self {
            ModelState::Crowd(tracker) => Some(tracker),
            ModelState::Glance(_) => None,
        }
    }

    /// The saliency and baseline models' state, if this is theirs.
    pub fn glance(&self) -> Option<&GlanceState> {
        match self {
            ModelState::Crowd(_) => None,
            ModelState::Glance(glance) => Some(glance),
        }
    }

    /// Where the saliency or baseline model wants the eyes and head (nowhere for the crowd
    /// model, whose target is its tracker's interest point).
    pub fn look(&self) -> Look {
        self.glance().map_or(Look::NONE, |glance| glance.look)
    }

    /// Drops every reference to a removed entity.
    pub fn forget(&mut self, id: u32) {
        match self {
            ModelState::Crowd(tracker) => tracker.forget(id),
            ModelState::Glance(glance) => glance.look.forget(id),
        }
    }
}

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

/// The five social target points of a chain (head, left eye, right eye, chest, torso) in the
/// character's frame at rest (metres), in the order of [`TargetPart::SOCIAL`].
pub fn social_parts(chain: &GazeChain, up: Vec3) -> [Vec3; 5] {
    let joints = chain.joints();
    let mut positions = [Vec3::ZERO; crate::ik::MAX_CHAIN_JOINTS];
    let mut position = chain.root_offset();
    let mut rotation = Quat::IDENTITY;
    let mut head_rotation = Quat::IDENTITY;
    for (index, joint) in joints.iter().enumerate().take(chain.body_count()) {
        position += rotation * joint.offset;
        rotation *= joint.rest;
        positions[index] = position;
        if joint.role == JointRole::Head {
            head_rotation = rotation;
        }
    }
    let head_joint = positions[chain.head_index()];
    let side = up
        .cross(head_rotation * chain.eye_forward())
        .normalize_or_zero();
    let (left, right) = match chain.eye_indices() {
        Some([left, right]) => (
            head_joint + head_rotation * joints[left].offset,
            head_joint + head_rotation * joints[right].offset,
        ),
        None => (head_joint + side * 0.032, head_joint - side * 0.032),
    };
    let head = 0.5 * (left + right) + up * 0.06;
    let spines = chain.spine_count().max(1);
    let chest = positions[spines - 1];
    let torso = positions[(spines - 1) / 2];
    [head, left, right, chest, torso]
}

impl Shared {
    /// The world point of `target` now (metres), if its entity exists.
    pub(super) fn target_point(&self, target: LookTarget) -> Option<Vec3> {
        let index = self.scene.index_of(target.entity)?;
        if target.part == TargetPart::Whole {
            return Some(self.scene.look_at_point(index));
        }
        let character = self.scene.character_at(index)?;
        let parts = &self.chain_parts[self.chain_of[character] as usize];
        let rotation = Quat::from_axis_angle(self.config.world.up, self.scene.headings()[index]);
        Some(self.scene.positions()[index] + rotation * parts[target.part as usize - 1])
    }

    /// A character's eye position (the mid-point of its eyes, world metres): where the
    /// last gaze update put it, or at rest before the first one.
    fn eye_position(&self, character: usize, motion: &GazeMotion) -> Vec3 {
        let origins = motion.eye_origins();
        if origins[0] != Vec3::ZERO || origins[1] != Vec3::ZERO {
            return 0.5 * (origins[0] + origins[1]);
        }
        let transform = self.character_transform(character);
        let chain = &self.chains[self.chain_of[character] as usize];
        transform.position + transform.rotation * chain.rest_eye_position()
    }

    /// The direction the character's head faces now (world, unit): the eyes' rest forward
    /// carried through the body joints' current local rotations.
    fn head_forward(&self, character: usize, motion: &GazeMotion) -> Vec3 {
        let chain = &self.chains[self.chain_of[character] as usize];
        let deltas = motion.deltas();
        let mut rotation = self.character_transform(character).rotation;
        let body = chain.body_count();
        let base = self.base_pose(character);
        for (base, delta) in base[..body].iter().zip(&deltas[..body]) {
            rotation *= *base * *delta;
        }
        (rotation * chain.eye_forward()).normalize_or_zero()
    }

    /// The saliency model for one character (Kokkinara et al. 2011): gathers the points
    /// (objects, and the five parts of characters) within `d_m`, scores them from the eyes,
    /// and renews the eye and head fixations when they run out or leave their field of view.
    pub(super) fn attend_saliency(&self, character: usize, dt: f32, state: CharacterMut<'_>) {
        let config = self.config.saliency;
        let up = self.config.world.up;
        let entity = self.scene.character_entities()[character] as usize;
        let eye = self.eye_position(character, state.motion);
        let head_forward = self.head_forward(character, state.motion);
        let body_forward = self
            .config
            .world
            .heading_direction(self.scene.headings()[entity]);
        let max_distance_squared = self.config.scoring.max_distance.powi(2);
        let centre = self.scene.ground_positions()[entity];

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
                    || self.scene.impacts()[index] <= 0.0
                {
                    return;
                }
                let candidate = (distance_squared, self.scene.ids()[index], other);
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
        let mut count = 0;
        'entities: for &(_, id, other) in near.iter() {
            let other = other as usize;
            let speed = self.scene.velocities()[other].length();
            let turn_rate = self.scene.turn_rates()[other];
            let is_character = self.scene.kinds()[other] == EntityKind::Character;
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
                if let Some(position) = self.target_point(target) {
                    points[count] = SalientPoint {
                        entity: id,
                        part: part as u8,
                        position,
                        speed,
                        turn_rate,
                        social: is_character,
                    };
                    count += 1;
                }
            }
        }
        let points = &points[..count];
        let mut in_eye = [0u8; MAX_SALIENT_POINTS];
        let mut in_head = [0u8; MAX_SALIENT_POINTS];
        let mut scores = [0.0f32; MAX_SALIENT_POINTS];
        let (mut eye_count, mut head_count) = (0, 0);
        for (index, point) in points.iter().enumerate() {
            let direction = point.position - eye;
            scores[index] = saliency(point, eye, head_forward, &config);
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
    /// proximity radius in front of it (never an object); the eyes glance at preset
    /// intervals.
    pub(super) fn attend_baseline(&self, character: usize, dt: f32, state: CharacterMut<'_>) {
        let entity = self.scene.character_entities()[character] as usize;
        let centre = self.scene.ground_positions()[entity];
        let radius_squared = self.config.baseline.proximity_radius.powi(2);
        let forward = self.scene.forwards()[entity];
        let mut nearest = (NO_ENTITY, f32::INFINITY);
        self.neighbours
            .grid()
            .for_each_near(centre, |other, ground| {
                let other = other as usize;
                let distance_squared = (ground - centre).length_squared();
                if other != entity
                    && forward.dot(ground - centre) >= 0.0
                    && self.scene.kinds()[other] == EntityKind::Character
                    && distance_squared <= radius_squared
                {
                    // Nearest by distance, then id (whatever order the grid visits them in).
                    let id = self.scene.ids()[other];
                    if (distance_squared, id) < (nearest.1, nearest.0) {
                        nearest = (id, distance_squared);
                    }
                }
            });
        let config = self.config.baseline;
        let ModelState::Glance(glance) = state.model else {
            return;
        };
        glance
            .baseline
            .update(dt, nearest.0, &config, state.model_random);
        let head = if nearest.0 == NO_ENTITY {
            LookTarget::NONE
        } else {
            LookTarget {
                entity: nearest.0,
                part: TargetPart::Head,
            }
        };
        glance.look = Look { eye: head, head };
    }

    /// The gaze request of a saliency or baseline character: head and eyes each at their
    /// own target (straight ahead where there is none; the baseline's glance offsets the
    /// eyes).
    pub(super) fn model_request(
        &self,
        character: usize,
        view: CharacterView<'_>,
    ) -> Option<GazeRequest> {
        let look = view.model.look();
        let entity = self.scene.character_entities()[character] as usize;
        let eye = self.eye_position(character, view.motion);
        let up = self.config.world.up;
        let ahead = self
            .config
            .world
            .heading_direction(self.scene.headings()[entity]);
        let head_point = self.target_point(look.head);
        let head_target = head_point.unwrap_or(eye + ahead * 10.0);
        let mut eye_target = self.target_point(look.eye).unwrap_or(head_target);
        if self.params[character].model == AttentionModel::Baseline {
            let (yaw, pitch) = view
                .model
                .glance()
                .map_or((0.0, 0.0), |state| state.baseline.glance);
            if yaw != 0.0 || pitch != 0.0 {
                let direction = (head_target - eye).normalize_or(ahead);
                let side = up.cross(direction).normalize_or_zero();
                let turned = Quat::from_axis_angle(up, yaw)
                    * Quat::from_axis_angle(side, -pitch)
                    * direction;
                eye_target = eye + turned * 10.0;
            }
        }
        if head_point.is_none()
            && self.target_point(look.eye).is_none()
            && eye_target == head_target
        {
            // Nothing to look at and no glance: let go, back to the base motion.
            return None;
        }
        // A new head target restarts the shift; the eyes follow theirs within it.
        let key = (u64::from(look.head.entity) << 3 | look.head.part as u64) | 1 << 40;
        Some(GazeRequest {
            target_key: key,
            head_target,
            eye_target,
            interest_ratio: 1.0,
            style: match self.params[character].model {
                AttentionModel::Saliency => MotionStyle::Saccadic,
                _ => MotionStyle::Eased,
            },
        })
    }

    /// The targets a character's eyes and head fixate (dense index), resolving explicit
    /// targets and the crowd model's interest point.
    pub(super) fn current_look(&self, character: usize, view: CharacterView<'_>) -> Look {
        let explicit = match self.explicit[character] {
            Some((ExplicitTarget::Entity(id), priority)) => Some((id, priority)),
            _ => None,
        };
        let automatic = match self.params[character].model {
            AttentionModel::Crowd => {
                let (target, _) = self.automatic_target(character, view.model.tracker());
                let target = LookTarget {
                    entity: target,
                    part: TargetPart::Whole,
                };
                Look {
                    eye: target,
                    head: target,
                }
            }
            _ => view.model.look(),
        };
        let automatic_exists = self.scene.index_of(automatic.head.entity).is_some()
            || self.scene.index_of(automatic.eye.entity).is_some();
        match explicit {
            Some((id, TargetPriority::Override)) => {
                let target = LookTarget {
                    entity: id,
                    part: TargetPart::Whole,
                };
                Look {
                    eye: target,
                    head: target,
                }
            }
            Some((id, TargetPriority::WhenIdle)) if !automatic_exists => {
                let target = LookTarget {
                    entity: id,
                    part: TargetPart::Whole,
                };
                Look {
                    eye: target,
                    head: target,
                }
            }
            _ => automatic,
        }
    }
}

impl Crowd {
    /// Makes the viewer (the user, or the camera) an entity that characters may look at,
    /// or moves it: `position` in metres (the point looked at), `impact` its `I_E`. Its
    /// velocity comes from successive calls at successive frame times; its heading from its
    /// motion. Returns its id; remove it with [`remove_entity`](Self::remove_entity).
    pub fn set_viewer(&mut self, position: Vec3, impact: f32) -> Result<u32> {
        ensure_all_finite(&position.to_array(), "viewer position")?;
        Self::check_impact(impact)?;
        self.ensure_online("set the viewer")?;
        let id = match self.shared.viewer {
            Some(id) => {
                let index = self
                    .shared
                    .scene
                    .index_of(id)
                    .ok_or_else(|| Error::Internal("the viewer entity is missing".into()))?;
                self.shared.scene.set_impact(index, impact);
                id
            }
            None => {
                let id = self
                    .shared
                    .scene
                    .add(EntityKind::Object, position, 0.0, 0.0, impact)?;
                self.shared.viewer = Some(id);
                id
            }
        };
        let time = if self.shared.time.is_finite() {
            self.shared.time
        } else {
            0.0
        };
        self.shared.scene.apply_one(
            time,
            &crate::scene::EntityUpdate {
                id,
                position,
                heading: 0.0,
                heading_from_motion: true,
                velocity: None,
            },
        );
        Ok(id)
    }

    /// The viewer's entity id, if set.
    pub fn viewer(&self) -> Option<u32> {
        self.shared.viewer
    }
}
