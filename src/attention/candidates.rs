//! Finding each character's best and second-best entity, fast.
//!
//! [`NeighbourIndex`] rebuilds the spatial grid every frame and copies what the scoring
//! needs (forward, velocity, impact, id) into grid order, so a query reads memory
//! sequentially whatever the crowd's size. A query visits the grid cells around the
//! character that may be in view; it tests distance, view and impact four entities at a
//! time in SIMD lanes and appends the slots that pass to a fixed-size [`CandidateBatch`]
//! without branching; the batch then gathers the survivors' data, scores them in one
//! straight-line loop that the compiler vectorises, and ranks them (skipping groups of
//! four below the second best). The all-pairs search feeds the same batch from every
//! entity, one at a time: the test oracle and the benchmark baseline.

use glam::{Vec2, Vec4};

use super::interest::Candidate;
use super::score::{
    orientation_score, periphery_score, proximity_score, speed_score, GroundState, Scorer,
    SubscoreWeights,
};
use crate::math::fast::fast_acos;
use crate::scene::grid::{SpatialGrid, SLOT_PADDING};
use crate::scene::Scene;

/// Candidates scored per batch (a denser neighbourhood is scored in several batches).
pub const BATCH: usize = 128;
const _: () = assert!(BATCH.is_power_of_two() && BATCH.is_multiple_of(4));

/// The grid and the scoring data of every entity in grid order, rebuilt each frame.
#[derive(Debug, Clone)]
pub struct NeighbourIndex {
    grid: SpatialGrid,
    forward: Vec<Vec2>,
    velocity: Vec<Vec2>,
    impact: Vec<f32>,
    id: Vec<u32>,
}

impl NeighbourIndex {
    /// An index for at most `capacity` entities and queries of radius `radius` (metres).
    pub fn new(capacity: usize, radius: f32) -> NeighbourIndex {
        NeighbourIndex {
            grid: SpatialGrid::new(capacity, radius),
            forward: vec![Vec2::ZERO; capacity],
            velocity: vec![Vec2::ZERO; capacity],
            impact: vec![0.0; capacity + SLOT_PADDING],
            id: vec![0; capacity],
        }
    }

    /// Rebuilds the grid and the grid-ordered copies from the scene's current state.
    pub fn rebuild(&mut self, scene: &Scene) {
        self.grid.rebuild(scene.ground_positions());
        let (forwards, velocities) = (scene.forwards(), scene.velocities());
        let (impacts, ids) = (scene.impacts(), scene.ids());
        for (slot, &entity) in self.grid.entries().iter().enumerate() {
            let entity = entity as usize;
            self.forward[slot] = forwards[entity];
            self.velocity[slot] = velocities[entity];
            self.impact[slot] = impacts[entity];
            self.id[slot] = ids[entity];
        }
    }

    /// Bytes of state per entity (grid-ordered copies and the grid's own arrays).
    pub fn bytes_per_entity() -> usize {
        use std::mem::size_of;
        // forward, velocity and grid point; impact; id and grid entry; and the grid's four
        // cell starts per entity.
        size_of::<Vec2>() * 3 + size_of::<f32>() + size_of::<u32>() * 2 + size_of::<u32>() * 4
    }

    /// The grid.
    pub fn grid(&self) -> &SpatialGrid {
        &self.grid
    }

    fn sources(&self) -> Sources<'_> {
        let (xs, ys) = self.grid.coordinates();
        Sources {
            points: Points::Split { xs, ys },
            entity: Some(self.grid.entries()),
            forward: &self.forward,
            velocity: &self.velocity,
            impact: &self.impact[..xs.len()],
            id: &self.id,
        }
    }
}

/// Where a search reads positions.
#[derive(Clone, Copy)]
enum Points<'a> {
    /// The scene's ground positions (slot = entity index).
    Interleaved(&'a [Vec2]),
    /// The grid's coordinates, x and y apart, followed by [`SLOT_PADDING`] values, as is
    /// the impact array: read four slots at a time.
    Split { xs: &'a [f32], ys: &'a [f32] },
}

/// Where a search reads entity data, by slot: the index's grid-ordered copies, or the
/// scene's own arrays (slot = entity index).
#[derive(Clone, Copy)]
struct Sources<'a> {
    points: Points<'a>,
    /// Entity index of each slot; `None` when the slot is the entity index.
    entity: Option<&'a [u32]>,
    forward: &'a [Vec2],
    velocity: &'a [Vec2],
    impact: &'a [f32],
    id: &'a [u32],
}

impl<'a> Sources<'a> {
    fn of_scene(scene: &'a Scene) -> Sources<'a> {
        Sources {
            points: Points::Interleaved(scene.ground_positions()),
            entity: None,
            forward: scene.forwards(),
            velocity: scene.velocities(),
            impact: scene.impacts(),
            id: scene.ids(),
        }
    }

    #[inline(always)]
    fn entity(&self, slot: usize) -> u32 {
        self.entity.map_or(slot as u32, |entities| entities[slot])
    }

    #[inline(always)]
    fn point(&self, slot: usize) -> Vec2 {
        match self.points {
            Points::Interleaved(points) => points[slot],
            Points::Split { xs, ys } => Vec2::new(xs[slot], ys[slot]),
        }
    }
}

/// Up to [`BATCH`] candidate slots, their data in structure-of-arrays form, and scores.
#[derive(Debug, Clone)]
pub struct CandidateBatch {
    len: usize,
    slot: [u32; BATCH],
    offset_x: [f32; BATCH],
    offset_y: [f32; BATCH],
    forward_x: [f32; BATCH],
    forward_y: [f32; BATCH],
    velocity_x: [f32; BATCH],
    velocity_y: [f32; BATCH],
    impact: [f32; BATCH],
    score: [f32; BATCH],
}

impl Default for CandidateBatch {
    fn default() -> Self {
        CandidateBatch {
            len: 0,
            slot: [0; BATCH],
            offset_x: [0.0; BATCH],
            offset_y: [0.0; BATCH],
            forward_x: [0.0; BATCH],
            forward_y: [0.0; BATCH],
            velocity_x: [0.0; BATCH],
            velocity_y: [0.0; BATCH],
            impact: [0.0; BATCH],
            score: [0.0; BATCH],
        }
    }
}

impl CandidateBatch {
    /// Copies the data of the batched slots from `sources`, relative to `observer`.
    fn gather(&mut self, sources: &Sources<'_>, observer: &GroundState) {
        for i in 0..self.len.min(BATCH) {
            let slot = self.slot[i] as usize;
            let offset = sources.point(slot) - observer.position;
            self.offset_x[i] = offset.x;
            self.offset_y[i] = offset.y;
            self.forward_x[i] = sources.forward[slot].x;
            self.forward_y[i] = sources.forward[slot].y;
            self.velocity_x[i] = sources.velocity[slot].x;
            self.velocity_y[i] = sources.velocity[slot].y;
            self.impact[i] = sources.impact[slot];
        }
    }

    /// Scores every candidate with the formulas of [`super::score`] (the same functions,
    /// so the results equal [`Scorer::score`]'s totals).
    fn score_all(&mut self, scorer: &Scorer, observer: &GroundState, weights: &SubscoreWeights) {
        let config = scorer.config();
        let half_field_of_view = 0.5 * config.field_of_view;
        let (speed_weight, periphery_max_angle) = (config.speed_weight, config.periphery_max_angle);
        let len = self.len.min(BATCH);
        for i in 0..len {
            let (offset_x, offset_y) = (self.offset_x[i], self.offset_y[i]);
            let distance = (offset_x * offset_x + offset_y * offset_y).sqrt();
            let along = observer.forward.x * offset_x + observer.forward.y * offset_y;
            // Divide unconditionally, then select: keeps the loop vectorisable.
            let quotient = along / distance.max(1e-6);
            let cos_view = if distance > 1e-6 { quotient } else { 1.0 };
            let view_angle = fast_acos(cos_view);
            let heading_angle = fast_acos(
                observer.forward.x * self.forward_x[i] + observer.forward.y * self.forward_y[i],
            );
            let relative_x = self.velocity_x[i] - observer.velocity.x;
            let relative_y = self.velocity_y[i] - observer.velocity.y;
            let relative_speed = (relative_x * relative_x + relative_y * relative_y).sqrt();
            self.score[i] = self.impact[i]
                * (weights.proximity * proximity_score(distance)
                    + weights.speed * speed_score(relative_speed, speed_weight)
                    + weights.orientation * orientation_score(view_angle, heading_angle)
                    + weights.periphery
                        * periphery_score(
                            view_angle,
                            heading_angle,
                            half_field_of_view,
                            periphery_max_angle,
                        ));
        }
    }
}

/// For each 4-bit mask of kept lanes: the kept lanes in order (then zeros) and their count.
const KEPT_LANES: [([u32; 4], usize); 16] = {
    let mut table = [([0u32; 4], 0usize); 16];
    let mut mask = 0;
    while mask < 16 {
        let mut count = 0;
        let mut lane = 0;
        while lane < 4 {
            if mask & (1 << lane) != 0 {
                table[mask].0[count] = lane as u32;
                count += 1;
            }
            lane += 1;
        }
        table[mask].1 = count;
        mask += 1;
    }
    table
};

/// True if `a` ranks above `b`: a higher score, or an equal score and a lower id (so the
/// ranking does not depend on the order entities are visited in). Nothing ranks below
/// the empty candidate.
#[inline]
fn ranks_above(a: Candidate, b: Candidate) -> bool {
    a.score > b.score || (a.score == b.score && a.id < b.id)
}

/// Keeps the two highest-ranked candidates.
#[inline]
fn rank(best: &mut Candidate, second: &mut Candidate, candidate: Candidate) {
    if ranks_above(candidate, *best) {
        *second = *best;
        *best = candidate;
    } else if ranks_above(candidate, *second) {
        *second = candidate;
    }
}

/// The view test without an arc cosine: is `offset` within the half field of view whose
/// cosine is `cos_half` of `forward`? (An entity at the observer's position is inside.)
#[inline(always)]
fn in_view(forward: Vec2, offset: Vec2, distance_squared: f32, cos_half: f32) -> bool {
    let along = forward.dot(offset);
    let bound = cos_half * cos_half * distance_squared;
    if cos_half >= 0.0 {
        (along >= 0.0) & (along * along >= bound)
    } else {
        (along >= 0.0) | (along * along <= bound)
    }
}

/// True if a grid cell (by its lowest and highest corners) may hold an entity in view of an
/// observer at `position` facing `forward`: with a field of view of at most 180°
/// (`cos_half_field_of_view ≥ 0` up to rounding), cells wholly behind the observer are
/// skipped.
#[inline]
fn cell_may_be_in_view(
    position: Vec2,
    forward: Vec2,
    cos_half_field_of_view: f32,
    low: Vec2,
    high: Vec2,
) -> bool {
    // cos(π/2) rounds to −4e−8 in f32: a 180° view must still cull.
    if cos_half_field_of_view < -1e-6 {
        return true;
    }
    let (low, high) = (low - position, high - position);
    // The largest dot product of `forward` with the cell's four corners.
    let best = forward.x.max(0.0) * high.x
        + forward.x.min(0.0) * low.x
        + forward.y.max(0.0) * high.y
        + forward.y.min(0.0) * low.y;
    best >= 0.0
}

/// One character's search: filters offered slots by distance and view, batches the
/// survivors, and keeps the best two.
struct Search<'a, Skip: FnMut(usize) -> bool> {
    scorer: &'a Scorer,
    weights: &'a SubscoreWeights,
    sources: Sources<'a>,
    observer: GroundState,
    observer_entity: u32,
    max_distance_squared: f32,
    cos_half_field_of_view: f32,
    batch: &'a mut CandidateBatch,
    skip: Skip,
    best: Candidate,
    second: Candidate,
}

impl<'a, Skip: FnMut(usize) -> bool> Search<'a, Skip> {
    fn new(
        scene: &Scene,
        sources: Sources<'a>,
        scorer: &'a Scorer,
        character: usize,
        weights: &'a SubscoreWeights,
        batch: &'a mut CandidateBatch,
        skip: Skip,
    ) -> Self {
        let observer_entity = scene.character_entities()[character];
        batch.len = 0;
        Search {
            scorer,
            weights,
            sources,
            observer: scene.ground_state(observer_entity as usize),
            observer_entity,
            max_distance_squared: scorer.max_distance_squared(),
            cos_half_field_of_view: (0.5 * scorer.config().field_of_view).cos(),
            batch,
            skip,
            best: Candidate::NONE,
            second: Candidate::NONE,
        }
    }

    /// Offers the slots `run`: each is kept for scoring if it is within `d_m`, in view and
    /// of positive impact. (The observer itself passes, and is left out when ranking.)
    #[inline(always)]
    fn offer_run(&mut self, run: std::ops::Range<usize>) {
        match self.sources.points {
            Points::Interleaved(points) => self.offer_interleaved(points, run),
            Points::Split { xs, ys } => self.offer_split(xs, ys, run),
        }
    }

    /// [`offer_run`](Self::offer_run) one slot at a time. Branch-free: each slot is
    /// written at the batch's end and kept only if it passes, so rejections cost no
    /// mispredicted branch.
    #[inline(always)]
    fn offer_interleaved(&mut self, points: &[Vec2], run: std::ops::Range<usize>) {
        let first = run.start;
        let impacts = &self.sources.impact[run.clone()];
        for (k, (point, impact)) in points[run].iter().zip(impacts).enumerate() {
            let offset = *point - self.observer.position;
            let distance_squared = offset.length_squared();
            let keep = (distance_squared <= self.max_distance_squared)
                & (*impact > 0.0)
                & in_view(
                    self.observer.forward,
                    offset,
                    distance_squared,
                    self.cos_half_field_of_view,
                );
            // len < BATCH (a full batch is flushed at once) and BATCH is a power of two:
            // the mask is a no-op that lets the compiler drop the bounds check.
            let i = self.batch.len % BATCH;
            self.batch.slot[i] = (first + k) as u32;
            self.batch.len = i + usize::from(keep);
            if self.batch.len == BATCH {
                self.flush();
            }
        }
    }

    /// [`offer_run`](Self::offer_run) four slots at a time, in SIMD lanes: the same tests
    /// with the same operations in the same order (so the same decisions), then the four
    /// slots written at the batch's end, each advancing it only if kept. Reads up to three
    /// slots past the run (the arrays are padded), masked off.
    #[inline(always)]
    fn offer_split(&mut self, xs: &[f32], ys: &[f32], run: std::ops::Range<usize>) {
        let position_x = Vec4::splat(self.observer.position.x);
        let position_y = Vec4::splat(self.observer.position.y);
        let forward_x = Vec4::splat(self.observer.forward.x);
        let forward_y = Vec4::splat(self.observer.forward.y);
        let max_distance_squared = Vec4::splat(self.max_distance_squared);
        let cos_half = self.cos_half_field_of_view;
        let bound_scale = Vec4::splat(cos_half * cos_half);
        let impacts = self.sources.impact;
        let mut slot = run.start;
        while slot < run.end {
            let lanes = (run.end - slot).min(4);
            let (Some(x), Some(y), Some(impact)) = (
                xs.get(slot..slot + 4),
                ys.get(slot..slot + 4),
                impacts.get(slot..slot + 4),
            ) else {
                // Only if the arrays were not padded: offer the rest one by one.
                return self.offer_split_tail(xs, ys, slot..run.end);
            };
            let offset_x = Vec4::from_slice(x) - position_x;
            let offset_y = Vec4::from_slice(y) - position_y;
            let distance_squared = offset_x * offset_x + offset_y * offset_y;
            let along = forward_x * offset_x + forward_y * offset_y;
            let bound = bound_scale * distance_squared;
            let ahead = along.cmpge(Vec4::ZERO);
            let in_view = if cos_half >= 0.0 {
                ahead & (along * along).cmpge(bound)
            } else {
                ahead | (along * along).cmple(bound)
            };
            let keep = distance_squared.cmple(max_distance_squared)
                & Vec4::from_slice(impact).cmpgt(Vec4::ZERO)
                & in_view;
            let mask = (keep.bitmask() & ((1u32 << lanes) - 1)) as usize;
            if self.batch.len > BATCH - 4 {
                self.flush();
            }
            // Compress: the kept lanes' slots, in order, to the batch's end (len ≤
            // BATCH − 4 here), then advance by their count.
            let batch = &mut *self.batch;
            let (kept, count) = KEPT_LANES[mask];
            let end = &mut batch.slot[batch.len..batch.len + 4];
            for (out, lane) in end.iter_mut().zip(kept) {
                *out = slot as u32 + lane;
            }
            batch.len += count;
            slot += 4;
        }
    }

    /// The last slots of a run without padding, one by one (not reached with the index's
    /// padded arrays; kept so that a short array cannot fault).
    #[cold]
    fn offer_split_tail(&mut self, xs: &[f32], ys: &[f32], run: std::ops::Range<usize>) {
        for slot in run {
            let offset = Vec2::new(xs[slot], ys[slot]) - self.observer.position;
            let distance_squared = offset.length_squared();
            if distance_squared <= self.max_distance_squared
                && self.sources.impact[slot] > 0.0
                && in_view(
                    self.observer.forward,
                    offset,
                    distance_squared,
                    self.cos_half_field_of_view,
                )
            {
                if self.batch.len == BATCH {
                    self.flush();
                }
                self.batch.slot[self.batch.len % BATCH] = slot as u32;
                self.batch.len += 1;
            }
        }
    }

    /// Gathers, scores and ranks the batch (consulting `skip` only for candidates that
    /// would enter the top two), and empties it.
    fn flush(&mut self) {
        let batch = &mut *self.batch;
        batch.gather(&self.sources, &self.observer);
        batch.score_all(self.scorer, &self.observer, self.weights);
        let len = batch.len.min(BATCH);
        // Four scores at a time: a group none of whose scores is positive and at least the
        // second best's (a tie may still rank above it, by id) is skipped whole.
        for group in (0..len).step_by(4) {
            let scores = Vec4::from_slice(&batch.score[group..group + 4]);
            let second = Vec4::splat(self.second.score);
            if !(scores.cmpge(second) & scores.cmpgt(Vec4::ZERO)).any() {
                continue;
            }
            for i in group..(group + 4).min(len) {
                let slot = batch.slot[i] as usize;
                let candidate = Candidate {
                    id: self.sources.id[slot],
                    score: batch.score[i],
                };
                if candidate.score > 0.0 && ranks_above(candidate, self.second) {
                    let entity = self.sources.entity(slot);
                    if entity == self.observer_entity || (self.skip)(entity as usize) {
                        continue;
                    }
                    rank(&mut self.best, &mut self.second, candidate);
                }
            }
        }
        batch.len = 0;
    }

    fn finish(mut self) -> (Candidate, Candidate) {
        self.flush();
        (self.best, self.second)
    }
}

/// The best and second-best entities (positive score) for the character at dense index
/// `character`, among the entities near it, skipping itself and every entity index for
/// which `skip` is true. `index` must have been rebuilt from the scene's current state;
/// `batch` is scratch space (reused, so that nothing is cleared per query).
pub fn nearby_candidates(
    scene: &Scene,
    index: &NeighbourIndex,
    scorer: &Scorer,
    character: usize,
    weights: &SubscoreWeights,
    batch: &mut CandidateBatch,
    skip: impl FnMut(usize) -> bool,
) -> (Candidate, Candidate) {
    let sources = index.sources();
    let mut search = Search::new(scene, sources, scorer, character, weights, batch, skip);
    let (position, forward) = (search.observer.position, search.observer.forward);
    let cos_half = search.cos_half_field_of_view;
    let keep_cell = |low, high| cell_may_be_in_view(position, forward, cos_half, low, high);
    index
        .grid
        .for_each_run_near_where(position, keep_cell, |run| search.offer_run(run));
    search.finish()
}

/// [`nearby_candidates`] by looking at every entity of the scene (the all-pairs loop),
/// kept as a test oracle and a benchmark baseline. Needs no index.
pub fn all_pairs_candidates(
    scene: &Scene,
    scorer: &Scorer,
    character: usize,
    weights: &SubscoreWeights,
    skip: impl FnMut(usize) -> bool,
) -> (Candidate, Candidate) {
    let mut batch = CandidateBatch::default();
    let sources = Sources::of_scene(scene);
    let mut search = Search::new(scene, sources, scorer, character, weights, &mut batch, skip);
    search.offer_run(0..scene.len());
    search.finish()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::random::Random;
    use crate::scene::ids::EntityKind;
    use crate::world::World;
    use std::f32::consts::PI;

    #[test]
    fn index_state_size() {
        // Part of a character's state (Crowd::state_bytes_per_character).
        assert_eq!(NeighbourIndex::bytes_per_entity(), 52);
    }

    #[test]
    fn ranking_keeps_the_top_two_and_breaks_ties_by_id() {
        let mut best = Candidate::NONE;
        let mut second = Candidate::NONE;
        for (id, score) in [(1, 0.2), (2, 0.5), (3, 0.1), (5, 0.4), (4, 0.4)] {
            rank(&mut best, &mut second, Candidate { id, score });
        }
        assert_eq!((best.id, second.id), (2, 4));
    }

    #[test]
    fn the_view_test_matches_the_angle() {
        let mut random = Random::new(4);
        for fov in [0.5f32, PI / 2.0, PI, 1.5 * PI, 2.0 * PI - 0.01] {
            let cos_half = (0.5 * fov).cos();
            for _ in 0..2000 {
                let forward = Vec2::from_angle(random.range(-PI, PI));
                let offset = Vec2::new(random.range(-5.0, 5.0), random.range(-5.0, 5.0));
                let angle = forward.angle_to(offset).abs();
                if (angle - 0.5 * fov).abs() < 1e-3 {
                    continue;
                }
                let inside = in_view(forward, offset, offset.length_squared(), cos_half);
                assert_eq!(inside, angle <= 0.5 * fov, "fov {fov}, angle {angle}");
            }
        }
    }

    /// `count` characters at random in a square of half side `half_extent`, facing random
    /// ways, with impacts from `impact(index, random)`.
    fn random_scene(
        count: usize,
        half_extent: f32,
        seed: u64,
        impact: impl Fn(usize, &mut Random) -> f32,
    ) -> Scene {
        let mut scene = Scene::new(World::y_up(), count as u32, 0);
        let mut random = Random::new(seed);
        for i in 0..count {
            let (x, z) = (
                random.range(-half_extent, half_extent),
                random.range(-half_extent, half_extent),
            );
            let heading = random.range(-PI, PI);
            let impact = impact(i, &mut random);
            scene
                .add(
                    EntityKind::Character,
                    glam::Vec3::new(x, 0.0, z),
                    heading,
                    1.6,
                    impact,
                )
                .unwrap();
        }
        scene
    }

    /// The grid search for `character`, skipping nothing.
    fn grid_search(
        scene: &Scene,
        index: &NeighbourIndex,
        scorer: &Scorer,
        character: usize,
        weights: &SubscoreWeights,
    ) -> (Candidate, Candidate) {
        let mut batch = CandidateBatch::default();
        nearby_candidates(scene, index, scorer, character, weights, &mut batch, |_| {
            false
        })
    }

    #[test]
    fn four_lane_filter_equals_the_one_by_one_filter() {
        // Dense (more candidates than a batch holds), with impacts of 0 among them.
        let scene = random_scene(700, 9.0, 21, |i, random| {
            if i % 7 == 0 {
                0.0
            } else {
                random.range(0.5, 2.0)
            }
        });
        let weights = SubscoreWeights::normalised([0.3, 0.2, 0.4, 0.1]).unwrap();
        let mut index = NeighbourIndex::new(700, 10.0);
        index.rebuild(&scene);
        // The scene's positions split into x and y, without padding: the last slots go
        // through the tail path.
        let xs: Vec<f32> = scene.ground_positions().iter().map(|p| p.x).collect();
        let ys: Vec<f32> = scene.ground_positions().iter().map(|p| p.y).collect();
        for field_of_view in [1.0, PI / 2.0, PI, 1.5 * PI, 2.0 * PI] {
            let scorer = Scorer::new(super::super::score::ScoringConfig {
                field_of_view,
                ..Default::default()
            });
            for character in (0..700).step_by(7) {
                let one_by_one =
                    all_pairs_candidates(&scene, &scorer, character, &weights, |_| false);
                let mut batch = CandidateBatch::default();
                let grid = grid_search(&scene, &index, &scorer, character, &weights);
                assert_eq!(grid, one_by_one, "grid, fov {field_of_view}");
                let sources = Sources {
                    points: Points::Split { xs: &xs, ys: &ys },
                    ..Sources::of_scene(&scene)
                };
                let mut search = Search::new(
                    &scene,
                    sources,
                    &scorer,
                    character,
                    &weights,
                    &mut batch,
                    |_| false,
                );
                search.offer_run(0..scene.len());
                assert_eq!(search.finish(), one_by_one, "unpadded, fov {field_of_view}");
            }
        }
    }

    #[test]
    fn batch_scores_equal_the_scorer() {
        let scorer = Scorer::new(Default::default());
        let scene = random_scene(200, 6.0, 8, |_, random| random.range(0.5, 2.0));
        let weights = SubscoreWeights::normalised([0.3, 0.2, 0.4, 0.1]).unwrap();
        let mut index = NeighbourIndex::new(200, 10.0);
        index.rebuild(&scene);
        for character in 0..200 {
            let (best, _) = grid_search(&scene, &index, &scorer, character, &weights);
            let observer = scene.character_entities()[character] as usize;
            let exact = (0..scene.len())
                .filter(|&other| other != observer)
                .map(|other| {
                    scorer
                        .score(
                            &scene.ground_state(observer),
                            &scene.ground_state(other),
                            &weights,
                            scene.impacts()[other],
                        )
                        .total
                })
                .fold(0.0, f32::max);
            assert!(
                (best.score - exact).abs() <= 1e-6,
                "{} vs {exact}",
                best.score
            );
        }
    }
}
