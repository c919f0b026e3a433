//! Finding each character's best and second-best entity, fast.
//!
//! [`NeighbourIndex`] rebuilds the spatial grid every frame and copies what the scoring
//! needs (heading, velocity, impact, id) into grid order, x and y apart, so that a query
//! reads memory sequentially whatever the crowd's size. A query visits the runs of grid
//! slots around the character that may be in view; it tests distance, view and impact for
//! a whole group of SIMD lanes at once (16 with AVX-512F, 8 with AVX, else 4, chosen at run
//! time; the same bits at every width) and compresses the survivors' data and ids into a
//! fixed-size [`CandidateBatch`] without branching. The batch is then scored a group at a
//! time, each lane keeping its two highest scores, and only the candidates at least the
//! batch's second-highest score — usually two — are ranked, with the ids the batch carries
//! (no lookup that waits on a load). The all-pairs search feeds the same batch from every
//! entity of the scene, one at a time, and scores it four lanes at a time: the test oracle
//! and the benchmark baseline.

use std::fmt::Display;

use glam::{Vec2, Vec4};

use super::interest::Candidate;
use super::score::{GroundState, LaneScorer, Scorer, SubscoreWeights};
use crate::alloc::{checked, try_clone, try_vec};
use crate::error::Result;
use crate::math::wide::{run_widest, LaneJob, Wide, MAX_LANES};
use crate::scene::grid::{SpatialGrid, RUN_ROOM, SLOT_PADDING};
use crate::scene::Scene;

/// Candidates scored per batch (a denser neighbourhood is scored in several batches).
pub const BATCH: usize = 128;
const _: () = assert!(BATCH.is_multiple_of(MAX_LANES));

/// Room in a batch's arrays: a full batch and one more group of lanes, so that a group
/// is always stored whole.
const BATCH_ROOM: usize = BATCH + MAX_LANES;

/// The grid and the scoring data of every entity in grid order, rebuilt each frame.
#[derive(Debug, Clone)]
pub struct NeighbourIndex {
    grid: SpatialGrid,
    // By grid slot, each followed by SLOT_PADDING values that belong to no slot (a query
    // reads whole groups of lanes).
    heading: Vec<f32>,
    velocity_x: Vec<f32>,
    velocity_y: Vec<f32>,
    impact: Vec<f32>,
    /// Id of the entity at each slot, as the bits of a float (moved through the float lanes
    /// into the batch, never computed with).
    id_bits: Vec<f32>,
    /// Grid slot of each entity.
    slot_of_entity: Vec<u32>,
    /// One past the last slot at which every grid-ordered array (the grid's coordinates
    /// too) holds a whole group of lanes: a query may load a group at any slot below it.
    /// Set by each rebuild from the arrays' lengths.
    group_slot_limit: usize,
}

impl NeighbourIndex {
    /// An index for at most `capacity` entities and queries of radius `radius` (metres);
    /// `what` names the caller's numbers `capacity` comes from, for
    /// [`Error::OutOfMemory`](crate::error::Error::OutOfMemory).
    pub fn new(capacity: usize, radius: f32, what: &dyn Display) -> Result<NeighbourIndex> {
        let padded = checked(capacity.checked_add(SLOT_PADDING), what)?;
        Ok(NeighbourIndex {
            grid: SpatialGrid::new(capacity, radius, what)?,
            heading: try_vec(padded, 0.0, what)?,
            velocity_x: try_vec(padded, 0.0, what)?,
            velocity_y: try_vec(padded, 0.0, what)?,
            impact: try_vec(padded, 0.0, what)?,
            id_bits: try_vec(padded, 0.0, what)?,
            slot_of_entity: try_vec(capacity, 0, what)?,
            group_slot_limit: 0,
        })
    }

    /// A copy of the index, or [`Error::OutOfMemory`](crate::error::Error::OutOfMemory)
    /// for `what`.
    pub fn try_clone(&self, what: &dyn Display) -> Result<NeighbourIndex> {
        Ok(NeighbourIndex {
            grid: self.grid.try_clone(what)?,
            heading: try_clone(&self.heading, what)?,
            velocity_x: try_clone(&self.velocity_x, what)?,
            velocity_y: try_clone(&self.velocity_y, what)?,
            impact: try_clone(&self.impact, what)?,
            id_bits: try_clone(&self.id_bits, what)?,
            slot_of_entity: try_clone(&self.slot_of_entity, what)?,
            group_slot_limit: self.group_slot_limit,
        })
    }

    /// Rebuilds the grid and the grid-ordered copies from the scene's current state; a
    /// talking entity's impact is copied times `talking_gain`
    /// ([`ScoringConfig::talking_gain`](super::score::ScoringConfig::talking_gain)).
    pub fn rebuild(&mut self, scene: &Scene, talking_gain: f32) {
        self.grid.rebuild(scene.ground_positions());
        let (headings, velocities) = (scene.headings(), scene.velocities());
        let ids = scene.ids();
        for (slot, &entity) in self.grid.entries().iter().enumerate() {
            let entity = entity as usize;
            self.heading[slot] = headings[entity];
            self.velocity_x[slot] = velocities[entity].x;
            self.velocity_y[slot] = velocities[entity].y;
            self.impact[slot] = scene.attention_impact(entity, talking_gain);
            self.id_bits[slot] = f32::from_bits(ids[entity]);
            self.slot_of_entity[entity] = slot as u32;
        }
        let (xs, ys) = self.grid.coordinates();
        let lengths = [
            xs.len(),
            ys.len(),
            self.heading.len(),
            self.velocity_x.len(),
            self.velocity_y.len(),
            self.impact.len(),
            self.id_bits.len(),
        ];
        let shortest = lengths.into_iter().min().unwrap_or(0);
        self.group_slot_limit = shortest.saturating_sub(SLOT_PADDING);
    }

    /// Bytes of state per entity (grid-ordered copies and the grid's own arrays).
    pub fn bytes_per_entity() -> usize {
        use std::mem::size_of;
        // velocity and grid point; heading and impact; id by slot, grid entry and slot of
        // each entity; and the grid's four cell starts per entity.
        size_of::<Vec2>() * 2 + size_of::<f32>() * 2 + size_of::<u32>() * 3 + size_of::<u32>() * 4
    }

    /// Hints the processor to load what a query by entity `entity` reads of the index
    /// before it reaches the grid (its slot).
    #[inline]
    pub fn prefetch_entity(&self, entity: usize) {
        crate::math::prefetch(self.slot_of_entity.as_ptr().wrapping_add(entity));
    }

    /// The grid.
    pub fn grid(&self) -> &SpatialGrid {
        &self.grid
    }
}

/// Up to [`BATCH`] candidates (and room for one more group of lanes), their data in
/// structure-of-arrays form, relative to the observer.
#[derive(Debug, Clone)]
pub struct CandidateBatch {
    len: usize,
    /// Each candidate's id, as the bits of a float: moved through float lanes with the
    /// rest, never computed with. (The all-pairs search puts entity indices here while it
    /// filters, and their ids once it gathers the data.)
    id_bits: [f32; BATCH_ROOM],
    offset_x: [f32; BATCH_ROOM],
    offset_y: [f32; BATCH_ROOM],
    heading: [f32; BATCH_ROOM],
    velocity_x: [f32; BATCH_ROOM],
    velocity_y: [f32; BATCH_ROOM],
    impact: [f32; BATCH_ROOM],
    /// Each candidate's score, once the batch is scored (0 past `len`).
    score: [f32; BATCH_ROOM],
}

impl Default for CandidateBatch {
    fn default() -> Self {
        CandidateBatch {
            len: 0,
            id_bits: [0.0; BATCH_ROOM],
            offset_x: [0.0; BATCH_ROOM],
            offset_y: [0.0; BATCH_ROOM],
            heading: [0.0; BATCH_ROOM],
            velocity_x: [0.0; BATCH_ROOM],
            velocity_y: [0.0; BATCH_ROOM],
            impact: [0.0; BATCH_ROOM],
            score: [0.0; BATCH_ROOM],
        }
    }
}

/// True if `a` ranks above `b`: a higher score, or an equal score and a lower id (so the
/// ranking does not depend on the order entities are visited in). Nothing ranks below
/// the empty candidate.
#[inline]
fn ranks_above(a: Candidate, b: Candidate) -> bool {
    a.score > b.score || (a.score == b.score && a.id < b.id)
}

/// Keeps the two highest-ranked candidates. Written as selects rather than branches: which
/// way a candidate goes is unpredictable, and conditional moves never mispredict.
#[inline]
fn rank(best: &mut Candidate, second: &mut Candidate, candidate: Candidate) {
    let (above_best, above_second) = (
        ranks_above(candidate, *best),
        ranks_above(candidate, *second),
    );
    let new_second = if above_best {
        *best
    } else if above_second {
        candidate
    } else {
        *second
    };
    *best = if above_best { candidate } else { *best };
    *second = new_second;
}

/// The view test without an arc cosine, one entity per lane: is `offset` within the half
/// field of view whose cosine is `cos_half` of the observer's forward direction? `along`
/// is `offset` projected on that direction. (An entity at the observer's position is
/// inside.)
#[inline(always)]
fn in_view<W: Wide>(along: W, distance_squared: W, cos_half: f32) -> W::Mask {
    let ahead = along.cmpge(W::splat(0.0));
    let along_squared = along * along;
    let bound = distance_squared * (cos_half * cos_half);
    if cos_half >= 0.0 {
        ahead & along_squared.cmpge(bound)
    } else {
        ahead | along_squared.cmple(bound)
    }
}

/// One character's ranking: who looks, how it scores, and its best two so far.
struct Ranking<'a, Skip: FnMut(u32) -> bool> {
    scorer: &'a Scorer,
    weights: &'a SubscoreWeights,
    observer: GroundState,
    observer_entity: u32,
    skip: Skip,
    best: Candidate,
    second: Candidate,
}

impl<'a, Skip: FnMut(u32) -> bool> Ranking<'a, Skip> {
    fn new(
        scene: &'a Scene,
        scorer: &'a Scorer,
        character: usize,
        weights: &'a SubscoreWeights,
        skip: Skip,
    ) -> Self {
        let observer_entity = scene.character_entities()[character];
        Ranking {
            scorer,
            weights,
            observer: scene.ground_state(observer_entity as usize),
            observer_entity,
            skip,
            best: Candidate::NONE,
            second: Candidate::NONE,
        }
    }

    /// Scores the batch a group of `W::LANES` at a time, then ranks the few candidates
    /// that could enter the top two (consulting `skip` only for those), and empties it.
    ///
    /// Scoring keeps each lane's two highest scores; from them comes a floor that at least
    /// two candidates of the batch reach (the comment at `floor` says why), and a candidate
    /// below it can no more enter the top two than one below `second` can. Usually two
    /// candidates are ranked. If one of those is skipped, the lower ones may count after
    /// all: the batch is ranked again from where it started, against `second` alone.
    #[inline(always)]
    fn flush<W: Wide>(&mut self, batch: &mut CandidateBatch) {
        let scorer = LaneScorer::<W>::new(self.scorer, &self.observer, self.weights);
        let len = batch.len;
        let (mut highest, mut next_highest) = (W::splat(0.0), W::splat(0.0));
        let mut group = 0;
        while group < len {
            // group < len ≤ BATCH + LANES − 1 and group is a multiple of LANES, which
            // divides BATCH, so group ≤ BATCH: a whole group fits in BATCH_ROOM (the min
            // changes nothing; it lets the compiler drop the bounds checks).
            let start = group.min(BATCH);
            let load = |values: &[f32; BATCH_ROOM]| W::load(&values[start..start + W::LANES]);
            let score = scorer.score(
                load(&batch.offset_x),
                load(&batch.offset_y),
                load(&batch.heading),
                load(&batch.velocity_x),
                load(&batch.velocity_y),
                load(&batch.impact),
            );
            let score = W::select(W::first_lanes(len - start), score, W::splat(0.0));
            score.store(&mut batch.score[start..start + W::LANES]);
            next_highest = next_highest.max(highest.min(score));
            highest = highest.max(score);
            group += W::LANES;
        }
        // Each lane gives a score other than the batch's highest one (the lanes holding the
        // highest score give their second): the largest of these is at most the batch's
        // second-highest score.
        let top = highest.reduce_max();
        let floor = W::select(highest.cmpeq(W::splat(top)), next_highest, highest).reduce_max();
        let before = (self.best, self.second);
        if self.rank_scored::<W>(batch, floor) {
            (self.best, self.second) = before;
            self.rank_scored::<W>(batch, 0.0);
        }
        batch.len = 0;
    }

    /// Ranks the scored candidates of the batch whose score is positive and at least
    /// `floor` and `second`'s, a group of lanes at a time. True if any was skipped.
    #[inline(always)]
    fn rank_scored<W: Wide>(&mut self, batch: &CandidateBatch, floor: f32) -> bool {
        let mut skipped = false;
        let mut group = 0;
        while group < batch.len {
            let start = group.min(BATCH);
            let score = W::load(&batch.score[start..start + W::LANES]);
            // Lanes with a positive score at least the second best's (a tie may still rank
            // above it, by id). Lanes past `len` scored 0.
            let rising =
                score.cmpge(W::splat(self.second.score.max(floor))) & score.cmpgt(W::splat(0.0));
            let mut lanes = W::bitmask(rising);
            while lanes != 0 {
                let lane = lanes.trailing_zeros() as usize;
                lanes &= lanes - 1;
                let candidate = Candidate {
                    id: batch.id_bits[start + lane].to_bits(),
                    score: batch.score[start + lane],
                };
                if ranks_above(candidate, self.second) {
                    if (self.skip)(candidate.id) {
                        skipped = true;
                        continue;
                    }
                    rank(&mut self.best, &mut self.second, candidate);
                }
            }
            group += W::LANES;
        }
        skipped
    }
}

/// One character's search of the grid: the runs of slots near it, filtered a group of
/// lanes at a time into the batch, which is ranked whenever it fills.
struct GridSearch<'a, Skip: FnMut(u32) -> bool> {
    ranking: Ranking<'a, Skip>,
    index: &'a NeighbourIndex,
    /// The forward direction whose half-plane the grid query keeps, if any.
    ahead: Option<Vec2>,
    /// The observer's own grid slot (it passes every test, and is no candidate).
    own_slot: usize,
    /// One past the last slot whose group of lanes every grid-ordered array holds.
    slot_limit: usize,
    batch: &'a mut CandidateBatch,
}

// For a reference, so that `run_widest` is handed a pointer: the search is built with
// narrow stores, and copying it whole for the call (wide loads of them) stalled the query.
impl<Skip: FnMut(u32) -> bool> LaneJob for &mut GridSearch<'_, Skip> {
    type Output = (Candidate, Candidate);

    #[inline(always)]
    fn run<W: Wide>(self) -> (Candidate, Candidate) {
        self.batch.len = 0;
        let observer = &self.ranking.observer;
        let runs = (self.index.grid).runs_near_lanes::<W>(observer.position, self.ahead);
        // The runs' first two groups of lanes each, listed without branching on their
        // lengths (an empty group is written and not counted); a longer run's rest is
        // offered on its own.
        let mut groups = [(0usize, 0usize); 2 * RUN_ROOM];
        let mut listed = 0;
        for &(first, end) in runs.as_slice() {
            let (first, end) = (first as usize, end as usize);
            let middle = (first + W::LANES).min(end);
            groups[listed % (2 * RUN_ROOM)] = (first, middle);
            listed += usize::from(first < end);
            groups[listed % (2 * RUN_ROOM)] = (middle, (middle + W::LANES).min(end));
            listed += usize::from(middle < end);
            if middle + W::LANES < end {
                self.offer::<W>(middle + W::LANES, end);
            }
        }
        for &(first, end) in &groups[..listed.min(2 * RUN_ROOM)] {
            self.offer_group::<W>(first, end);
        }
        self.ranking.flush::<W>(self.batch);
        (self.ranking.best, self.ranking.second)
    }
}

impl<Skip: FnMut(u32) -> bool> GridSearch<'_, Skip> {
    /// Offers grid slots `first .. end`, a group of lanes at a time (see
    /// [`offer_group`](Self::offer_group)).
    #[inline(always)]
    fn offer<W: Wide>(&mut self, first: usize, end: usize) {
        let mut slot = first;
        while slot < end {
            self.offer_group::<W>(slot, end.min(slot + W::LANES));
            slot += W::LANES;
        }
    }

    /// Offers grid slots `first .. end` (at most `W::LANES` of them) in one group of lanes:
    /// each is kept if it is within `d_m`, in view and of positive impact, and is not the
    /// observer's own slot. The kept lanes' data are compressed to the batch's end (all
    /// lanes are stored, none counted if none is kept: no branch to mispredict).
    /// Reads up to `LANES − 1` slots past `end` (the arrays are padded), masked off.
    #[inline(always)]
    fn offer_group<W: Wide>(&mut self, first: usize, end: usize) {
        let index = self.index;
        let (xs, ys) = index.grid.coordinates();
        // Checked here for the unchecked loads below: the arrays hold SLOT_PADDING ≥
        // LANES − 1 values past every slot (so this never fails).
        assert!(first < end && end - first <= W::LANES && end <= self.slot_limit);
        let load = |values: &[f32]| {
            // SAFETY: first + LANES ≤ end + SLOT_PADDING ≤ the length of each array, checked
            // above (slot_limit is the least of them minus SLOT_PADDING).
            unsafe { W::load_at(values, first) }
        };
        let observer = &self.ranking.observer;
        let offset_x = load(xs) - W::splat(observer.position.x);
        let offset_y = load(ys) - W::splat(observer.position.y);
        let impact = load(&index.impact);
        let distance_squared = offset_x * offset_x + offset_y * offset_y;
        let along =
            W::splat(observer.forward.x) * offset_x + W::splat(observer.forward.y) * offset_y;
        let own_slot = self.own_slot;
        let keep = distance_squared.cmple(W::splat(self.ranking.scorer.max_distance_squared()))
            & impact.cmpgt(W::splat(0.0))
            & in_view::<W>(along, distance_squared, self.ranking.scorer.cos_half_field_of_view())
            & W::first_lanes(end - first)
            // Not lane own_slot − first (no lane when it is outside 0 .. LANES).
            & !(W::first_lanes((own_slot + 1).saturating_sub(first))
                & !W::first_lanes(own_slot.saturating_sub(first)));
        if self.batch.len >= BATCH {
            self.ranking.flush::<W>(self.batch);
        }
        let batch = &mut *self.batch;
        let at = batch.len;
        let store = |values: W, out: &mut [f32; BATCH_ROOM]| {
            // SAFETY: at < BATCH after the flush above, so at + LANES ≤ BATCH_ROOM.
            unsafe { values.compress_store_at(keep, out, at) }
        };
        store(load(&index.id_bits), &mut batch.id_bits);
        store(offset_x, &mut batch.offset_x);
        store(offset_y, &mut batch.offset_y);
        store(load(&index.heading), &mut batch.heading);
        store(load(&index.velocity_x), &mut batch.velocity_x);
        store(load(&index.velocity_y), &mut batch.velocity_y);
        store(impact, &mut batch.impact);
        batch.len = at + W::bitmask(keep).count_ones() as usize;
    }
}

/// The grid search for `character`, ready to run at any width (what
/// [`nearby_candidates`] runs at the widest width the processor has).
fn grid_search<'a, Skip: FnMut(u32) -> bool>(
    scene: &'a Scene,
    index: &'a NeighbourIndex,
    scorer: &'a Scorer,
    character: usize,
    weights: &'a SubscoreWeights,
    batch: &'a mut CandidateBatch,
    skip: Skip,
) -> GridSearch<'a, Skip> {
    let ranking = Ranking::new(scene, scorer, character, weights, skip);
    // With a field of view of at most 180° (cos(π/2) rounds to −4e−8 in f32, and a 180°
    // view must still cull), cells wholly behind the observer are skipped.
    let observer = &ranking.observer;
    let ahead = (scorer.cos_half_field_of_view() >= -1e-6).then_some(observer.forward);
    let own_slot = index.slot_of_entity[ranking.observer_entity as usize] as usize;
    GridSearch {
        ranking,
        index,
        ahead,
        own_slot,
        slot_limit: index.group_slot_limit,
        batch,
    }
}

/// The best and second-best entities (positive score) for the character at dense index
/// `character`, among the entities near it, skipping itself and every entity for which
/// `skip(id)` is true. `index` must have been rebuilt from the scene's current state;
/// `batch` is scratch space (reused, so that nothing is cleared per query).
pub fn nearby_candidates(
    scene: &Scene,
    index: &NeighbourIndex,
    scorer: &Scorer,
    character: usize,
    weights: &SubscoreWeights,
    batch: &mut CandidateBatch,
    skip: impl FnMut(u32) -> bool,
) -> (Candidate, Candidate) {
    run_widest(&mut grid_search(
        scene, index, scorer, character, weights, batch, skip,
    ))
}

/// [`nearby_candidates`] by looking at every entity of the scene (the all-pairs loop),
/// kept as a test oracle and a benchmark baseline. Needs no index. Filters one entity at a
/// time (branch-free: each is written at the batch's end and kept only if it passes) and
/// scores four lanes at a time.
pub fn all_pairs_candidates(
    scene: &Scene,
    scorer: &Scorer,
    character: usize,
    weights: &SubscoreWeights,
    skip: impl FnMut(u32) -> bool,
) -> (Candidate, Candidate) {
    let mut batch = CandidateBatch::default();
    let mut ranking = Ranking::new(scene, scorer, character, weights, skip);
    let observer = ranking.observer;
    let (max_distance_squared, cos_half) = (
        scorer.max_distance_squared(),
        scorer.cos_half_field_of_view(),
    );
    let gain = scorer.config().talking_gain;
    let impacts = scene.impacts();
    for (entity, (point, impact)) in scene.ground_positions().iter().zip(impacts).enumerate() {
        let offset = *point - observer.position;
        let distance_squared = offset.length_squared();
        let keep = (distance_squared <= max_distance_squared)
            & (*impact > 0.0)
            & in_view::<f32>(observer.forward.dot(offset), distance_squared, cos_half)
            & (entity != ranking.observer_entity as usize);
        // len < BATCH (a full batch is ranked at once).
        let at = batch.len % BATCH;
        batch.id_bits[at] = f32::from_bits(entity as u32);
        batch.len = at + usize::from(keep);
        if batch.len == BATCH {
            gather_from_scene(&mut batch, scene, &observer, gain);
            ranking.flush::<Vec4>(&mut batch);
        }
    }
    gather_from_scene(&mut batch, scene, &observer, gain);
    ranking.flush::<Vec4>(&mut batch);
    (ranking.best, ranking.second)
}

/// Fills the batch's data from the scene's arrays, by the entity indices it holds, and
/// replaces those with the entities' ids.
fn gather_from_scene(
    batch: &mut CandidateBatch,
    scene: &Scene,
    observer: &GroundState,
    talking_gain: f32,
) {
    let (points, headings) = (scene.ground_positions(), scene.headings());
    let velocities = scene.velocities();
    let ids = scene.ids();
    for i in 0..batch.len.min(BATCH) {
        let entity = batch.id_bits[i].to_bits() as usize;
        batch.id_bits[i] = f32::from_bits(ids[entity]);
        let offset = points[entity] - observer.position;
        batch.offset_x[i] = offset.x;
        batch.offset_y[i] = offset.y;
        batch.heading[i] = headings[entity];
        batch.velocity_x[i] = velocities[entity].x;
        batch.velocity_y[i] = velocities[entity].y;
        batch.impact[i] = scene.attention_impact(entity, talking_gain);
    }
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
                let inside = in_view::<f32>(forward.dot(offset), offset.length_squared(), cos_half);
                assert_eq!(inside, angle <= 0.5 * fov, "fov {fov}, angle {angle}");
            }
        }
    }

    /// `count` characters at random in a square of half side `half_extent`, facing random
    /// ways, with impacts from `impact(index, random)`; every tenth is the twin of the one
    /// before (same place, heading and impact: the same score, ranked by id).
    fn random_scene(
        count: usize,
        half_extent: f32,
        seed: u64,
        impact: impl Fn(usize, &mut Random) -> f32,
    ) -> Scene {
        let mut scene = Scene::new(World::y_up(), count as u32, 0, &"test").unwrap();
        let mut random = Random::new(seed);
        let mut previous = (0.0, 0.0, 0.0, 0.0);
        for i in 0..count {
            if i % 10 != 9 {
                previous = (
                    random.range(-half_extent, half_extent),
                    random.range(-half_extent, half_extent),
                    random.range(-PI, PI),
                    impact(i, &mut random),
                );
            }
            let (x, z, heading, impact) = previous;
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

    /// The grid search for `character` at width `W`, skipping the entities for which
    /// `skip(id)` is true.
    fn search_at<W: Wide>(
        scene: &Scene,
        index: &NeighbourIndex,
        scorer: &Scorer,
        character: usize,
        weights: &SubscoreWeights,
        skip: impl FnMut(u32) -> bool,
    ) -> (Candidate, Candidate) {
        let mut batch = CandidateBatch::default();
        let mut search = grid_search(scene, index, scorer, character, weights, &mut batch, skip);
        (&mut search).run::<W>()
    }

    /// The grid search at width `W` equals the all-pairs search on a dense scene (more
    /// candidates than a batch holds) with impacts of 0 and equal scores among them, for
    /// fields of view narrow to full; and again when the two best and every eleventh id
    /// are skipped (so the skipped ones are among those that could enter the top two).
    fn grid_equals_all_pairs<W: Wide>() {
        let scene = random_scene(700, 9.0, 21, |i, random| {
            if i % 7 == 0 {
                0.0
            } else {
                random.range(0.5, 2.0)
            }
        });
        let weights = SubscoreWeights::normalised([0.3, 0.2, 0.4, 0.1]).unwrap();
        let mut index = NeighbourIndex::new(700, 10.0, &"test").unwrap();
        index.rebuild(&scene, 1.0);
        for field_of_view in [1.0, PI / 2.0, PI, 1.5 * PI, 2.0 * PI] {
            let scorer = Scorer::new(super::super::score::ScoringConfig {
                field_of_view,
                ..Default::default()
            });
            for character in (0..700).step_by(7) {
                let all_pairs =
                    all_pairs_candidates(&scene, &scorer, character, &weights, |_| false);
                let grid = search_at::<W>(&scene, &index, &scorer, character, &weights, |_| false);
                assert_eq!(grid, all_pairs, "{} lanes, fov {field_of_view}", W::LANES);
                let skipped =
                    |id: u32| id == all_pairs.0.id || id == all_pairs.1.id || id.is_multiple_of(11);
                let all_pairs = all_pairs_candidates(&scene, &scorer, character, &weights, skipped);
                let grid = search_at::<W>(&scene, &index, &scorer, character, &weights, skipped);
                assert_eq!(
                    grid,
                    all_pairs,
                    "{} lanes, fov {field_of_view}, skipping",
                    W::LANES
                );
            }
        }
    }

    #[test]
    fn grid_search_equals_all_pairs_at_every_width() {
        crate::math::wide::for_every_width!(grid_equals_all_pairs());
    }

    #[test]
    fn batch_scores_equal_the_scorer() {
        let scorer = Scorer::new(Default::default());
        let scene = random_scene(200, 6.0, 8, |_, random| random.range(0.5, 2.0));
        let weights = SubscoreWeights::normalised([0.3, 0.2, 0.4, 0.1]).unwrap();
        let mut index = NeighbourIndex::new(200, 10.0, &"test").unwrap();
        index.rebuild(&scene, 1.0);
        for character in 0..200 {
            let mut batch = CandidateBatch::default();
            let (best, _) = nearby_candidates(
                &scene,
                &index,
                &scorer,
                character,
                &weights,
                &mut batch,
                |_| false,
            );
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
