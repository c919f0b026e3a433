//! The scene: every entity's current state in flat arrays (structure of arrays), its id,
//! and the per-frame ingestion of positions and headings with velocities derived by
//! finite differences.
//!
//! Entities are stored densely in `0..len()`: removal swaps the last entity into the hole
//! (ids stay valid; indices do not). Characters are also listed densely, in creation order
//! up to swap-removal, with the entity index of each. All arrays are sized at creation.

pub mod grid;
pub mod ids;
mod ingest;
pub mod order;

pub use ingest::{EntityUpdate, SceneWriter, MAX_SPEED, MIN_SPEED_FOR_HEADING};

use glam::{Vec2, Vec3};

use crate::alloc::{try_clone, try_with_capacity, Field};
use crate::error::{Error, Result};
use crate::math::wrap_angle;
use crate::world::World;
use ids::{EntityKind, IdTable, NO_ENTITY};
use order::Reorder;

/// Runs `$body` with `$array` bound to each per-entity array of `$scene` in turn, so that
/// removing and reordering entities move every array alike.
macro_rules! each_entity_array {
    ($scene:ident, $array:ident => $body:expr) => {
        each_entity_array!(@arrays $scene, $array => $body; id, kind, character, position,
            look_at_height, ground, heading, forward, velocity, turn_rate, impact, last_time, talking)
    };
    (@arrays $scene:ident, $array:ident => $body:expr; $($name:ident),*) => {{
        $({
            let $array = &mut $scene.$name;
            $body;
        })*
    }};
}

/// One entity's state on the ground plane, gathered by [`Scene::ground_state`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GroundState {
    /// Position on the ground plane (metres).
    pub position: Vec2,
    /// Unit forward direction on the ground plane.
    pub forward: Vec2,
    /// Heading (radians) in [−π, π] (π only by rounding): the angle of `forward` (see
    /// [`crate::math::wrap_angle`]).
    pub heading: f32,
    /// Velocity on the ground plane (m/s).
    pub velocity: Vec2,
}

/// The entities of a crowd.
#[derive(Debug, Clone)]
pub struct Scene {
    world: World,
    ids: IdTable,
    max_characters: u32,
    max_objects: u32,
    character_count: u32,
    object_count: u32,
    // Per entity (dense).
    id: Vec<u32>,
    kind: Vec<EntityKind>,
    /// Dense character index of a character entity, `NO_ENTITY` for objects.
    character: Vec<u32>,
    position: Vec<Vec3>,
    look_at_height: Vec<f32>,
    ground: Vec<Vec2>,
    heading: Vec<f32>,
    forward: Vec<Vec2>,
    velocity: Vec<Vec2>,
    /// Turn rate about up (rad/s), from successive headings.
    turn_rate: Vec<f32>,
    impact: Vec<f32>,
    last_time: Vec<f64>,
    /// True while the entity talks (the last pushed state's `talking`).
    talking: Vec<bool>,
    // Per character (dense).
    character_entity: Vec<u32>,
    /// Largest impact factor of any live entity (`S_MAX`).
    max_impact: f32,
}

impl Scene {
    /// An empty scene with room for the given numbers of characters and objects; `what`
    /// names the caller's numbers the entity arrays are sized from, for
    /// [`Error::OutOfMemory`].
    pub fn new(
        world: World,
        max_characters: u32,
        max_objects: u32,
        what: &dyn std::fmt::Display,
    ) -> Result<Scene> {
        let capacity = (max_characters + max_objects) as usize;
        let characters = Field("max_characters", max_characters.into());
        Ok(Scene {
            world,
            ids: IdTable::new(max_characters + max_objects, what)?,
            max_characters,
            max_objects,
            character_count: 0,
            object_count: 0,
            id: try_with_capacity(capacity, what)?,
            kind: try_with_capacity(capacity, what)?,
            character: try_with_capacity(capacity, what)?,
            position: try_with_capacity(capacity, what)?,
            look_at_height: try_with_capacity(capacity, what)?,
            ground: try_with_capacity(capacity, what)?,
            heading: try_with_capacity(capacity, what)?,
            forward: try_with_capacity(capacity, what)?,
            velocity: try_with_capacity(capacity, what)?,
            turn_rate: try_with_capacity(capacity, what)?,
            impact: try_with_capacity(capacity, what)?,
            last_time: try_with_capacity(capacity, what)?,
            talking: try_with_capacity(capacity, what)?,
            character_entity: try_with_capacity(max_characters as usize, &characters)?,
            max_impact: 0.0,
        })
    }

    /// A copy of the scene that keeps every array's room to grow (as `clone` does not), or
    /// [`Error::OutOfMemory`] for `what`.
    pub fn try_clone(&self, what: &dyn std::fmt::Display) -> Result<Scene> {
        Ok(Scene {
            world: self.world,
            ids: self.ids.try_clone(what)?,
            max_characters: self.max_characters,
            max_objects: self.max_objects,
            character_count: self.character_count,
            object_count: self.object_count,
            id: try_clone(&self.id, what)?,
            kind: try_clone(&self.kind, what)?,
            character: try_clone(&self.character, what)?,
            position: try_clone(&self.position, what)?,
            look_at_height: try_clone(&self.look_at_height, what)?,
            ground: try_clone(&self.ground, what)?,
            heading: try_clone(&self.heading, what)?,
            forward: try_clone(&self.forward, what)?,
            velocity: try_clone(&self.velocity, what)?,
            turn_rate: try_clone(&self.turn_rate, what)?,
            impact: try_clone(&self.impact, what)?,
            last_time: try_clone(&self.last_time, what)?,
            talking: try_clone(&self.talking, what)?,
            character_entity: try_clone(&self.character_entity, what)?,
            max_impact: self.max_impact,
        })
    }

    /// Bytes of state per entity (all the per-entity arrays and the id table).
    pub fn bytes_per_entity() -> usize {
        use std::mem::size_of;
        size_of::<u32>() * 2 // id, character index
            + size_of::<EntityKind>()
            + size_of::<Vec3>() // position
            + size_of::<f32>() * 4 // look-at height, heading, turn rate, impact
            + size_of::<Vec2>() * 3 // ground, forward, velocity
            + size_of::<f64>() // last time
            + size_of::<bool>() // talking
            + IdTable::bytes_per_entity()
    }

    /// The world conventions.
    pub fn world(&self) -> &World {
        &self.world
    }

    /// Number of live entities.
    pub fn len(&self) -> usize {
        self.id.len()
    }

    /// True if there are no entities.
    pub fn is_empty(&self) -> bool {
        self.id.is_empty()
    }

    /// Number of live characters.
    pub fn character_count(&self) -> usize {
        self.character_entity.len()
    }

    /// Adds an entity; `position` in metres, `heading` in radians. Returns its id.
    pub fn add(
        &mut self,
        kind: EntityKind,
        position: Vec3,
        heading: f32,
        look_at_height: f32,
        impact: f32,
    ) -> Result<u32> {
        match kind {
            EntityKind::Character if self.character_count >= self.max_characters => {
                return Err(Error::Capacity(format!(
                    "the crowd already holds max_characters = {} characters",
                    self.max_characters
                )))
            }
            EntityKind::Object if self.object_count >= self.max_objects => {
                return Err(Error::Capacity(format!(
                    "the crowd already holds max_objects = {} objects",
                    self.max_objects
                )))
            }
            _ => {}
        }
        let index = self.id.len() as u32;
        let id = self.ids.insert(kind, index)?;
        let ground = self.world.ground(position);
        self.id.push(id);
        self.kind.push(kind);
        self.position.push(position);
        self.look_at_height.push(look_at_height);
        self.ground.push(ground);
        self.heading.push(wrap_angle(heading));
        self.forward.push(Vec2::from_angle(heading));
        self.velocity.push(Vec2::ZERO);
        self.turn_rate.push(0.0);
        self.impact.push(impact);
        self.last_time.push(f64::NEG_INFINITY);
        self.talking.push(false);
        match kind {
            EntityKind::Character => {
                self.character.push(self.character_entity.len() as u32);
                self.character_entity.push(index);
                self.character_count += 1;
            }
            EntityKind::Object => {
                self.character.push(NO_ENTITY);
                self.object_count += 1;
            }
        }
        self.max_impact = self.max_impact.max(impact);
        Ok(id)
    }

    /// Removes an entity. Returns the dense character index it had, if it was a character
    /// (the last character now sits there), so per-character state can be swapped too.
    pub fn remove(&mut self, id: u32) -> Result<Option<u32>> {
        let (kind, index) = self.ids.find(id)?;
        self.ids.remove(id)?;
        let index = index as usize;
        let last = self.id.len() - 1;
        let removed_character = self.character[index];
        if index != last {
            let moved_id = self.id[last];
            self.ids.relocate(moved_id, index as u32);
            let moved_character = self.character[last];
            if moved_character != NO_ENTITY {
                self.character_entity[moved_character as usize] = index as u32;
            }
        }
        each_entity_array!(self, array => {
            array.swap_remove(index);
        });
        match kind {
            EntityKind::Character => {
                let slot = removed_character as usize;
                let last_character = self.character_entity.len() - 1;
                if slot != last_character {
                    let moved_entity = self.character_entity[last_character];
                    self.character[moved_entity as usize] = slot as u32;
                }
                self.character_entity.swap_remove(slot);
                self.character_count -= 1;
            }
            EntityKind::Object => self.object_count -= 1,
        }
        self.max_impact = self.impact.iter().copied().fold(0.0, f32::max);
        Ok((kind == EntityKind::Character).then_some(removed_character))
    }

    /// Stores the entities in a new order — entity `i` is the one at index `order[i]`
    /// before — and the characters in the order their entities now come in. Ids stay
    /// valid; entity and character indices change. Writes to `characters` each character's
    /// old index, in the new character order (the order the caller's per-character arrays
    /// take, with [`Reorder::apply`]). Allocates nothing (`characters` has room for every
    /// character). `order` must be a permutation of `0..len()`, as the spatial grid's
    /// entries are: otherwise this panics, before changing anything.
    pub fn reorder(&mut self, order: &[u32], reorder: &mut Reorder, characters: &mut Vec<u32>) {
        assert!(
            order.len() == self.id.len() && reorder.is_permutation(order),
            "a scene order must list every entity once"
        );
        each_entity_array!(self, array => reorder.apply(array, order));
        characters.clear();
        let entities = self.id.iter().zip(&mut self.character).zip(order);
        for (index, ((&id, character), &old)) in entities.enumerate() {
            if old as usize != index {
                self.ids.relocate(id, index as u32);
            }
            if *character != NO_ENTITY {
                let new_character = characters.len();
                characters.push(*character);
                self.character_entity[new_character] = index as u32;
                *character = new_character as u32;
            }
        }
    }

    /// Kind and entity index of a live id.
    pub fn find(&self, id: u32) -> Result<(EntityKind, usize)> {
        self.ids
            .find(id)
            .map(|(kind, index)| (kind, index as usize))
    }

    /// Entity index of a live id, if any.
    #[inline]
    pub fn index_of(&self, id: u32) -> Option<usize> {
        self.ids.lookup(id).map(|(_, index)| index as usize)
    }

    /// Dense character index of the character at entity index `index`, if it is one.
    pub fn character_at(&self, index: usize) -> Option<usize> {
        let character = self.character[index];
        (character != NO_ENTITY).then_some(character as usize)
    }

    /// Dense character index of a live character id.
    pub fn character_index(&self, id: u32) -> Result<usize> {
        let (kind, index) = self.find(id)?;
        if kind != EntityKind::Character {
            return Err(Error::InvalidArgument(format!(
                "entity {id} is an object, not a character"
            )));
        }
        Ok(self.character[index] as usize)
    }

    /// Checks one update without changing anything (the id exists and the values are
    /// finite) and returns its entity's index, for [`SceneWriter::apply_at`].
    pub fn check_update(&self, update: &EntityUpdate) -> Result<usize> {
        ingest::check(&self.ids, update)
    }

    /// A writer of pushed states into this scene's entities, for several threads at once.
    pub fn writer(&mut self) -> SceneWriter<'_> {
        SceneWriter::new(
            self.world,
            &self.ids,
            &self.id,
            ingest::PushedArrays {
                position: &mut self.position,
                ground: &mut self.ground,
                heading: &mut self.heading,
                forward: &mut self.forward,
                velocity: &mut self.velocity,
                turn_rate: &mut self.turn_rate,
                last_time: &mut self.last_time,
                talking: &mut self.talking,
            },
        )
    }

    /// Applies one frame of updates at time `time` (seconds). Velocities come from the
    /// caller or from the difference with the entity's previous sample; entities not in
    /// `updates` keep their last state. Check each with [`check_update`](Self::check_update)
    /// first: unknown ids are skipped here.
    pub fn apply(&mut self, time: f64, updates: &[EntityUpdate]) {
        for update in updates {
            self.apply_one(time, update);
        }
    }

    /// Applies one update at time `time` (see [`apply`](Self::apply)); an unknown id is
    /// skipped.
    pub fn apply_one(&mut self, time: f64, update: &EntityUpdate) {
        if let Some(index) = self.index_of(update.id) {
            // SAFETY: the index of a live id is in range; `&mut self` keeps every other
            // access out.
            unsafe { self.writer().apply_at(index, time, update) };
        }
    }

    /// Sets an entity's impact factor, keeping `S_MAX` current: the maximum is scanned again
    /// only when the entity that held it lowers its impact (so the viewer, whose impact is
    /// set every frame, costs O(1)).
    pub fn set_impact(&mut self, index: usize, impact: f32) {
        let previous = std::mem::replace(&mut self.impact[index], impact);
        if impact >= self.max_impact {
            self.max_impact = impact;
        } else if previous >= self.max_impact {
            self.max_impact = self.impact.iter().copied().fold(0.0, f32::max);
        }
    }

    /// `S_MAX`: the largest impact factor of any live entity (the largest possible score).
    pub fn max_impact(&self) -> f32 {
        self.max_impact
    }

    /// Ids, by entity index.
    pub fn ids(&self) -> &[u32] {
        &self.id
    }
    /// Kinds, by entity index.
    pub fn kinds(&self) -> &[EntityKind] {
        &self.kind
    }
    /// Root positions (metres), by entity index.
    pub fn positions(&self) -> &[Vec3] {
        &self.position
    }
    /// Look-at heights above the root (metres), by entity index.
    pub fn look_at_heights(&self) -> &[f32] {
        &self.look_at_height
    }
    /// Ground-plane positions, by entity index.
    pub fn ground_positions(&self) -> &[Vec2] {
        &self.ground
    }
    /// Headings (radians, wrapped into [−π, π] by [`wrap_angle`]), by entity index.
    pub fn headings(&self) -> &[f32] {
        &self.heading
    }
    /// Unit ground forward directions, by entity index.
    pub fn forwards(&self) -> &[Vec2] {
        &self.forward
    }
    /// Ground velocities (m/s), by entity index.
    pub fn velocities(&self) -> &[Vec2] {
        &self.velocity
    }
    /// Turn rates about up (rad/s), by entity index.
    pub fn turn_rates(&self) -> &[f32] {
        &self.turn_rate
    }
    /// Entity `index`'s impact factor as attention sees it: times `talking_gain` while it
    /// talks.
    #[inline]
    pub fn attention_impact(&self, index: usize, talking_gain: f32) -> f32 {
        if self.talking[index] {
            self.impact[index] * talking_gain
        } else {
            self.impact[index]
        }
    }
    /// Whether each entity talks (its last pushed state's flag), by entity index.
    pub fn talking(&self) -> &[bool] {
        &self.talking
    }
    /// Impact factors, by entity index.
    pub fn impacts(&self) -> &[f32] {
        &self.impact
    }
    /// Entity index of each character, by dense character index.
    pub fn character_entities(&self) -> &[u32] {
        &self.character_entity
    }

    /// The world look-at point of an entity (metres): its root plus its look-at height
    /// along up.
    pub fn look_at_point(&self, index: usize) -> Vec3 {
        self.position[index] + self.world.up * self.look_at_height[index]
    }

    /// The ground-plane state the scoring function needs, of one entity.
    #[inline]
    pub fn ground_state(&self, index: usize) -> GroundState {
        GroundState {
            position: self.ground[index],
            forward: self.forward[index],
            heading: self.heading[index],
            velocity: self.velocity[index],
        }
    }

    /// Sets an entity's look-at height (metres).
    pub fn set_look_at_height(&mut self, index: usize, height: f32) {
        self.look_at_height[index] = height;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn update(id: u32, x: f32, z: f32) -> EntityUpdate {
        EntityUpdate {
            id,
            position: Vec3::new(x, 0.0, z),
            heading: 0.0,
            heading_from_motion: true,
            velocity: None,
            talking: false,
        }
    }

    #[test]
    fn entity_state_size() {
        // Part of a character's state (Crowd::state_bytes_per_character).
        assert_eq!(Scene::bytes_per_entity(), 78);
    }

    #[test]
    fn velocities_and_headings_come_from_motion() {
        let mut scene = Scene::new(World::y_up(), 4, 4, &"test").unwrap();
        let a = scene
            .add(EntityKind::Character, Vec3::ZERO, 0.3, 1.6, 1.0)
            .unwrap();
        scene.apply(0.0, &[update(a, 0.0, 0.0)]);
        // Y up, Z forward: moving along +X is heading +90°.
        scene.apply(0.5, &[update(a, 1.0, 0.0)]);
        let index = scene.index_of(a).unwrap();
        assert!(scene.velocities()[index].abs_diff_eq(Vec2::new(0.0, 2.0), 1e-6));
        assert!((scene.headings()[index] - std::f32::consts::FRAC_PI_2).abs() < 1e-6);
        // Standing still keeps the heading.
        scene.apply(1.0, &[update(a, 1.0, 0.0)]);
        assert!((scene.headings()[index] - std::f32::consts::FRAC_PI_2).abs() < 1e-6);
        assert_eq!(scene.velocities()[index], Vec2::ZERO);
    }

    #[test]
    fn turn_rates_of_large_headings_are_their_change() {
        // Headings are kept wrapped; the turn must come from the wrapped new heading too,
        // not from the raw one (whose f32 remainder drifts by far more than the turn).
        let mut scene = Scene::new(World::y_up(), 4, 4, &"test").unwrap();
        let a = scene
            .add(EntityKind::Character, Vec3::ZERO, 1.0e6, 1.6, 1.0)
            .unwrap();
        let index = scene.index_of(a).unwrap();
        let turned = |heading| EntityUpdate {
            heading,
            heading_from_motion: false,
            ..update(a, 0.0, 0.0)
        };
        scene.apply(0.0, &[turned(1.0e6)]);
        scene.apply(0.5, &[turned(1.0e6 + 0.5)]);
        let rate = scene.turn_rates()[index];
        assert!((rate - 1.0).abs() < 1e-4, "{rate}");
    }

    #[test]
    fn speeds_are_limited_and_finite() {
        // Found by the fuzz target: a jump across the f32 range overflowed the velocity.
        let mut scene = Scene::new(World::y_up(), 4, 4, &"test").unwrap();
        let a = scene
            .add(EntityKind::Character, Vec3::ZERO, 0.0, 1.6, 1.0)
            .unwrap();
        let index = scene.index_of(a).unwrap();
        scene.apply(0.0, &[update(a, -3.0e38, 0.0)]);
        scene.apply(1.0e-30, &[update(a, 3.0e38, 0.0)]);
        let speed = scene.velocities()[index].length();
        assert!((speed - MAX_SPEED).abs() <= MAX_SPEED * 1e-6, "{speed}");
        let mut given = update(a, 0.0, 0.0);
        given.velocity = Some(Vec3::new(f32::MAX, 0.0, f32::MAX));
        scene.apply(2.0, &[given]);
        let velocity = scene.velocities()[index];
        assert!(
            (velocity.length() - MAX_SPEED).abs() <= MAX_SPEED * 1e-6,
            "{velocity}"
        );
        given.velocity = Some(Vec3::new(3.0, 0.0, 4.0));
        scene.apply(3.0, &[given]);
        assert!((scene.velocities()[index].length() - 5.0).abs() < 1e-6);
    }

    #[test]
    fn removal_keeps_other_ids_and_character_indices_valid() {
        let mut scene = Scene::new(World::y_up(), 3, 2, &"test").unwrap();
        let a = scene
            .add(EntityKind::Character, Vec3::X, 0.0, 1.6, 1.0)
            .unwrap();
        let o = scene
            .add(EntityKind::Object, Vec3::Y, 0.0, 1.0, 3.0)
            .unwrap();
        let b = scene
            .add(EntityKind::Character, Vec3::Z, 0.0, 1.6, 1.0)
            .unwrap();
        assert_eq!(scene.max_impact(), 3.0);
        assert_eq!(scene.remove(a).unwrap(), Some(0));
        assert!(scene.find(a).is_err());
        assert_eq!(scene.character_index(b).unwrap(), 0);
        let b_index = scene.index_of(b).unwrap();
        assert_eq!(scene.positions()[b_index], Vec3::Z);
        assert_eq!(scene.character_entities()[0] as usize, b_index);
        assert_eq!(scene.remove(o).unwrap(), None);
        assert_eq!(scene.max_impact(), 1.0);
        assert!(scene.character_index(b).is_ok());
        let full = Scene::new(World::y_up(), 0, 0, &"test").unwrap().add(
            EntityKind::Object,
            Vec3::ZERO,
            0.0,
            0.0,
            1.0,
        );
        assert!(matches!(full, Err(Error::Capacity(_))));
    }
}
