//! A uniform grid over the ground plane, rebuilt every frame without allocation.
//!
//! Each rebuild fits the grid to the points' bounding box with cells `radius / 8` wide and
//! `radius / 2` tall (larger if the box would need more cells than the grid has room for),
//! and counting-sorts the points by cell, row by row. A query of the grid's radius then
//! reads the 5 rows around a point, each row clipped to the circle (and, if asked, to the
//! half-plane in front), as one contiguous run of the sorted points per row — no hashing,
//! no duplicates, and sequential memory. Tall rows keep the runs few; narrow columns let
//! each run end close to the circle and the half-plane (at 0.25 points/m² a query facing
//! one way offers 58 points, against 81 with square cells of radius / 2, for the 39 within
//! reach in front). The rows are clipped in SIMD lanes, as many at once as the lanes hold,
//! without a branch per row.

use std::fmt::Display;

use glam::Vec2;

use crate::alloc::{checked, try_clone, try_vec};
use crate::error::Result;
use crate::math::wide::{clamp, Wide, MAX_LANES};

/// Extra coordinates after the last slot, so that a query may read a whole group of SIMD
/// lanes (up to 16) from any slot without running off the arrays (what it reads there, it
/// masks off).
pub const SLOT_PADDING: usize = crate::math::wide::MAX_LANES - 1;

/// Most runs one query makes: one per row, at most 7 rows (a query spans at most 3 rows
/// each way, as rows are at least half the radius tall).
pub const MAX_RUNS: usize = 2 * MAX_SPAN as usize + 1;

/// Largest number of rows a query spans each way from its centre's row.
const MAX_SPAN: i32 = 3;

/// Columns per query radius: cells are `radius / 8` wide and `radius / 2` tall (or larger
/// for a sprawling scene). Narrow columns clip each row's run close to the circle and the
/// half-plane; tall rows keep the runs few.
const COLUMNS_PER_RADIUS: f32 = 8.0;

/// Largest number of columns a query spans each way from its centre's column.
const MAX_COLUMN_SPAN: i32 = COLUMNS_PER_RADIUS as i32 + 1;

/// Room for the runs of one query: [`MAX_RUNS`] rounded up to a power of two (so that
/// storing a run masks its index rather than dividing it).
pub(crate) const RUN_ROOM: usize = MAX_RUNS.next_power_of_two();

/// Most cells a grid has: 2²³, so that row and column numbers are exact in an `f32` (a
/// query clips rows in SIMD lanes, in floats).
const MOST_CELLS: usize = 1 << 23;

/// `⌊x⌋` as an integer, saturating (far-away points stay valid), without a call to
/// `floorf` (which x86-64's baseline instructions lack).
#[inline]
fn floor_to_i32(x: f32) -> i32 {
    let truncated = x as i32;
    if (truncated as f32) > x {
        truncated.saturating_sub(1)
    } else {
        truncated
    }
}

/// The runs of grid slots one query covers, each a contiguous range of slots.
#[derive(Debug, Clone, Copy)]
pub struct SlotRuns {
    runs: [(u32, u32); RUN_ROOM],
    len: usize,
}

impl SlotRuns {
    /// The runs, each as (first slot, end slot).
    #[inline]
    pub fn as_slice(&self) -> &[(u32, u32)] {
        &self.runs[..self.len]
    }
}

/// The grid: `cell_start[c] .. cell_start[c + 1]` indexes `entries`, `xs` and `ys` for
/// cell `c`.
#[derive(Debug, Clone)]
pub struct SpatialGrid {
    radius: f32,
    /// Width and height of a cell.
    cell_size: Vec2,
    inverse_cell_size: Vec2,
    origin: Vec2,
    columns: i32,
    rows: i32,
    /// Columns and rows a query spans each way from its centre's cell (set by each
    /// rebuild).
    column_span: i32,
    row_span: i32,
    /// Most cells the grid may use (sized at creation).
    max_cells: usize,
    cell_start: Vec<u32>,
    entries: Vec<u32>,
    /// Coordinates of the points in slot order, split (x and y apart, so that a query
    /// loads four of each at once), with [`SLOT_PADDING`] more at the end.
    xs: Vec<f32>,
    ys: Vec<f32>,
    /// Points in the last rebuild.
    len: usize,
}

impl SpatialGrid {
    /// A grid for at most `capacity` points, answering queries of radius `radius` (metres);
    /// `what` names the caller's numbers `capacity` comes from, for [`Error::OutOfMemory`].
    ///
    /// [`Error::OutOfMemory`]: crate::error::Error::OutOfMemory
    pub fn new(capacity: usize, radius: f32, what: &dyn Display) -> Result<SpatialGrid> {
        let max_cells = capacity.max(1).saturating_mul(4).clamp(64, MOST_CELLS);
        let padded = checked(capacity.checked_add(SLOT_PADDING), what)?;
        Ok(SpatialGrid {
            radius,
            cell_size: Vec2::new(radius / COLUMNS_PER_RADIUS, radius / 2.0),
            inverse_cell_size: Vec2::new(COLUMNS_PER_RADIUS / radius, 2.0 / radius),
            origin: Vec2::ZERO,
            columns: 1,
            rows: 1,
            column_span: MAX_COLUMN_SPAN,
            row_span: MAX_SPAN,
            max_cells,
            cell_start: try_vec(max_cells + 1, 0, what)?,
            entries: try_vec(capacity, 0, what)?,
            xs: try_vec(padded, 0.0, what)?,
            ys: try_vec(padded, 0.0, what)?,
            len: 0,
        })
    }

    /// A copy of the grid, or [`Error::OutOfMemory`] for `what`.
    ///
    /// [`Error::OutOfMemory`]: crate::error::Error::OutOfMemory
    pub fn try_clone(&self, what: &dyn Display) -> Result<SpatialGrid> {
        Ok(SpatialGrid {
            cell_start: try_clone(&self.cell_start, what)?,
            entries: try_clone(&self.entries, what)?,
            xs: try_clone(&self.xs, what)?,
            ys: try_clone(&self.ys, what)?,
            ..*self
        })
    }

    /// Width and height of a cell in metres (an eighth and half of the query radius, or
    /// more for a sprawling scene).
    pub fn cell_size(&self) -> Vec2 {
        self.cell_size
    }

    #[inline]
    fn cell_of(&self, point: Vec2) -> (i32, i32) {
        let scaled = (point - self.origin) * self.inverse_cell_size;
        (floor_to_i32(scaled.x), floor_to_i32(scaled.y))
    }

    /// The cell holding `point`, one of the points of the rebuild: within the grid's box, so
    /// its scaled coordinates are ≥ 0 and truncating them is their floor (no call to
    /// `floorf`, which x86-64's baseline instructions lack). Those on the box's far edges
    /// count in the last column or row.
    #[inline]
    fn cell_index(&self, point: Vec2) -> usize {
        let scaled = (point - self.origin) * self.inverse_cell_size;
        let (x, y) = (scaled.x as i32, scaled.y as i32);
        (y.clamp(0, self.rows - 1) * self.columns + x.clamp(0, self.columns - 1)) as usize
    }

    /// Rebuilds the grid from `points` (finite): entry `i` of the grid is point index `i`.
    /// Points beyond the capacity given at creation are ignored.
    pub fn rebuild(&mut self, points: &[Vec2]) {
        let count = points.len().min(self.entries.len());
        let points = &points[..count];
        self.len = count;
        let (mut low, mut high) = (Vec2::splat(f32::MAX), Vec2::splat(f32::MIN));
        for point in points {
            low = low.min(*point);
            high = high.max(*point);
        }
        if count == 0 {
            low = Vec2::ZERO;
            high = Vec2::ZERO;
        }
        // Cells of radius/8 × radius/2, grown until the bounding box fits in max_cells. A
        // box wider than a float holds (points near ±f32::MAX) counts as f32::MAX wide, or
        // the doubling below would never end.
        let extent = (high - low).max(Vec2::ZERO).min(Vec2::splat(f32::MAX));
        let mut cell_size = Vec2::new(self.radius / COLUMNS_PER_RADIUS, self.radius / 2.0);
        loop {
            let columns = (extent.x / cell_size.x).floor() as f64 + 1.0;
            let rows = (extent.y / cell_size.y).floor() as f64 + 1.0;
            if columns * rows <= self.max_cells as f64 {
                self.columns = columns as i32;
                self.rows = rows as i32;
                break;
            }
            cell_size *= 2.0;
        }
        self.cell_size = cell_size;
        self.inverse_cell_size = cell_size.recip();
        // Cells are at least radius / 8 wide and radius / 2 tall, so the spans are 8 and 2
        // (one more by rounding), or less for grown cells.
        let spans = (self.radius * self.inverse_cell_size).ceil();
        self.column_span = (spans.x as i32).clamp(0, MAX_COLUMN_SPAN);
        self.row_span = (spans.y as i32).clamp(0, MAX_SPAN);
        self.origin = low;
        let cells = (self.columns * self.rows) as usize;
        self.cell_start[..=cells].fill(0);
        for point in points {
            let cell = self.cell_index(*point);
            self.cell_start[cell + 1] += 1;
        }
        for cell in 1..=cells {
            self.cell_start[cell] += self.cell_start[cell - 1];
        }
        // Scatter, using cell_start[c] as a cursor, then shift the starts back. (Each point's
        // cell is computed again rather than kept from the count: 4 bytes less per entity,
        // for a few instructions.)
        for (index, point) in points.iter().enumerate() {
            let cell = self.cell_index(*point);
            let cursor = self.cell_start[cell] as usize;
            self.entries[cursor] = index as u32;
            self.xs[cursor] = point.x;
            self.ys[cursor] = point.y;
            self.cell_start[cell] = cursor as u32 + 1;
        }
        for cell in (1..=cells).rev() {
            self.cell_start[cell] = self.cell_start[cell - 1];
        }
        self.cell_start[0] = 0;
    }

    /// Point index of each grid slot (the points sorted by cell, row by row).
    pub fn entries(&self) -> &[u32] {
        &self.entries[..self.len]
    }

    /// The point in grid slot `slot`.
    #[inline]
    pub fn point(&self, slot: usize) -> Vec2 {
        Vec2::new(self.xs[slot], self.ys[slot])
    }

    /// The points' x and y coordinates in grid-slot order, each followed by
    /// [`SLOT_PADDING`] values that belong to no slot.
    #[inline]
    pub fn coordinates(&self) -> (&[f32], &[f32]) {
        let end = self.len + SLOT_PADDING;
        (&self.xs[..end], &self.ys[..end])
    }

    /// Calls `visit(slots)` with contiguous ranges of grid slots that together hold every
    /// point within the grid's radius of `centre` (see [`runs_near`](Self::runs_near)).
    #[inline]
    pub fn for_each_run_near(&self, centre: Vec2, mut visit: impl FnMut(std::ops::Range<usize>)) {
        for &(first, end) in self.runs_near(centre, None).as_slice() {
            visit(first as usize..end as usize);
        }
    }

    /// How far (metres) a query around `centre` widens the rows it clips: far above the
    /// rounding of the coordinates it compares (a few units in the last place of the
    /// largest, about 1e−7 of it), so that no point that belongs is left out.
    fn rounding_margin(&self, centre: Vec2) -> f32 {
        0.01 * self.cell_size.min_element()
            + 1e-6 * (centre.abs().element_sum() + self.origin.abs().element_sum())
    }

    /// The runs of grid slots that together hold every point within the grid's radius of
    /// `centre` — whole cells, so a superset: the cells of the rows around it, each row
    /// clipped to the circle — and, if `ahead` is given, of those only the cells that reach
    /// the half-plane in front of `centre` facing `ahead` (`ahead · (p − centre) ≥ 0`).
    /// One run per row (empty where the row has no such cell); each slot comes once.
    pub fn runs_near(&self, centre: Vec2, ahead: Option<Vec2>) -> SlotRuns {
        self.runs_near_lanes::<f32>(centre, ahead)
    }

    /// [`runs_near`](Self::runs_near), clipping `W::LANES` rows at a time (the same
    /// operations in every lane, so the same runs at every width). A row with no cell to
    /// visit gets an empty run.
    #[inline(always)]
    pub(crate) fn runs_near_lanes<W: Wide>(&self, centre: Vec2, ahead: Option<Vec2>) -> SlotRuns {
        let mut runs = SlotRuns {
            runs: [(0, 0); RUN_ROOM],
            len: 0,
        };
        let (column_span, row_span) = (self.column_span, self.row_span);
        let (cx, cy) = self.cell_of(centre);
        let first_column = cx.saturating_sub(column_span).max(0);
        let last_column = cx.saturating_add(column_span).min(self.columns - 1);
        let first_row = cy.saturating_sub(row_span).max(0);
        let last_row = cy.saturating_add(row_span).min(self.rows - 1);
        if first_column > last_column {
            return runs;
        }
        let height = self.cell_size.y;
        let margin = self.rounding_margin(centre);
        let radius_squared = self.radius * self.radius;
        // Column numbers, exact in floats (at most MOST_CELLS cells).
        let (lowest, past_highest) = (first_column as f32, (last_column + 1) as f32);
        let column_of = |x: W| (x - self.origin.x) * self.inverse_cell_size.x;
        let (centre_x, centre_y) = (W::splat(centre.x), W::splat(centre.y));
        // Divided once per query (the margin covers the rounding of the products).
        let inverse_forward_x = ahead.map_or(0.0, |forward| 1.0 / forward.x);
        let mut row = first_row;
        while row <= last_row {
            let rows = (last_row - row + 1) as usize;
            let low_y = (W::splat(row as f32) + W::lane_numbers()) * height + self.origin.y;
            let high_y = low_y + height;
            // The circle: the row's points lie within `reach` of the centre in x.
            let gap_y = (low_y - centre_y).max(centre_y - high_y).max(W::splat(0.0));
            let mut beyond = gap_y.cmpgt(W::splat(self.radius + margin));
            let reach = (W::splat(radius_squared) - gap_y * gap_y)
                .max(W::splat(0.0))
                .sqrt()
                + margin;
            let (mut low_x, mut high_x) = (centre_x - reach, centre_x + reach);
            if let Some(forward) = ahead {
                // A cell reaches the half-plane if `forward · (corner − centre) ≥ 0` at its
                // best corner: the row fixes the y part, which bounds the x part.
                let most_y = (high_y - centre_y) * forward.y.max(0.0)
                    + (low_y - centre_y) * forward.y.min(0.0);
                if forward.x > 0.0 {
                    // Cells whose right edge is at least this.
                    low_x = low_x.max(centre_x - most_y * inverse_forward_x - margin);
                } else if forward.x < 0.0 {
                    // Cells whose left edge is at most this.
                    high_x = high_x.min(centre_x - most_y * inverse_forward_x + margin);
                } else {
                    beyond |= most_y.cmplt(W::splat(0.0));
                }
            }
            // The first column, at least first_column ≥ 0 (so truncating is the floor), and
            // one past the last as ⌊x + 1⌋, at least 0 (x + 1 may round up to a whole
            // number: one cell more, never one fewer). An empty run starts past the last.
            let firsts = W::select(
                beyond,
                W::splat(past_highest),
                clamp(column_of(low_x), lowest, past_highest),
            );
            let ends = clamp(column_of(high_x) + 1.0, 0.0, past_highest);
            let (mut first_at, mut end_at) = ([0.0; MAX_LANES], [0.0; MAX_LANES]);
            firsts.store(&mut first_at);
            ends.store(&mut end_at);
            for (lane, (first, end)) in first_at
                .iter()
                .zip(&end_at)
                .take(rows.min(W::LANES))
                .enumerate()
            {
                let (first, end) = (*first as usize, *end as usize);
                // first ≤ end ≤ last_column + 1 ≤ columns: both starts are within the row
                // or the next row's first.
                let row_start = (row as usize + lane) * self.columns as usize;
                // At most 2 · MAX_SPAN + 1 rows, one run each: within RUN_ROOM.
                runs.runs[runs.len % RUN_ROOM] = (
                    self.cell_start[row_start + first],
                    self.cell_start[row_start + end.max(first)],
                );
                runs.len += 1;
            }
            row += W::LANES as i32;
        }
        runs
    }

    /// Calls `visit(index, point)` for every point [`for_each_run_near`](Self::for_each_run_near)
    /// covers.
    #[inline]
    pub fn for_each_near(&self, centre: Vec2, mut visit: impl FnMut(u32, Vec2)) {
        self.for_each_run_near(centre, |run| {
            for slot in run {
                visit(self.entries[slot], self.point(slot));
            }
        });
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::random::Random;

    /// `count` points drawn from `random` uniformly within `half_size` of `centre`, and a
    /// grid of radius 10 m and room for `capacity` points rebuilt from them.
    fn scattered(
        random: &mut Random,
        count: usize,
        half_size: Vec2,
        centre: Vec2,
        capacity: usize,
    ) -> (Vec<Vec2>, SpatialGrid) {
        let points: Vec<Vec2> = (0..count)
            .map(|_| {
                let x = random.range(-half_size.x, half_size.x);
                Vec2::new(x, random.range(-half_size.y, half_size.y)) + centre
            })
            .collect();
        let mut grid = SpatialGrid::new(capacity, 10.0, &"test").unwrap();
        grid.rebuild(&points);
        (points, grid)
    }

    #[test]
    fn finds_every_point_within_the_radius_exactly_once() {
        let (points, grid) =
            scattered(&mut Random::new(3), 500, Vec2::splat(60.0), Vec2::ZERO, 600);
        let mut centres = points[..50].to_vec();
        centres.push(Vec2::new(-200.0, 300.0));
        for centre in &centres {
            let mut visited = vec![0u32; points.len()];
            grid.for_each_near(*centre, |i, p| {
                assert_eq!(p, points[i as usize]);
                visited[i as usize] += 1;
            });
            for (i, point) in points.iter().enumerate() {
                assert!(visited[i] <= 1);
                if point.distance(*centre) <= 10.0 {
                    assert_eq!(visited[i], 1, "point {i} missed");
                }
            }
        }
    }

    #[test]
    fn floor_matches_the_library_floor() {
        for x in [
            -3.5f32,
            -3.0,
            -0.2,
            -0.0,
            0.0,
            0.7,
            2.0,
            1e9,
            -1e9,
            3e9,
            -3e9,
            f32::NAN,
        ] {
            assert_eq!(floor_to_i32(x), x.floor() as i32, "{x}");
        }
    }

    #[test]
    fn sprawling_scenes_grow_the_cells_instead_of_the_memory() {
        let points = [
            Vec2::new(-1e6, 1e6),
            Vec2::new(1e6, -1e6),
            Vec2::ZERO,
            Vec2::new(3.0, 4.0),
        ];
        let mut grid = SpatialGrid::new(4, 10.0, &"test").unwrap();
        grid.rebuild(&points);
        assert!(grid.cell_size().x > 10.0 / COLUMNS_PER_RADIUS && grid.cell_size().y > 5.0);
        let mut near = Vec::new();
        grid.for_each_near(Vec2::ZERO, |i, _| near.push(i));
        assert!(near.contains(&2) && near.contains(&3));
        grid.rebuild(&[]);
        grid.for_each_near(Vec2::ZERO, |_, _| panic!("empty grid"));
    }

    /// Queries `grid` (of `points`) around 40 of its points facing `forward`: every point
    /// within the radius in front is visited, only cells that reach the front are, and
    /// none more than the unculled query visits. Returns the slots visited, culled and not.
    fn check_culled_query(grid: &SpatialGrid, points: &[Vec2], forward: Vec2) -> (usize, usize) {
        let (mut total_visited, mut total_all) = (0, 0);
        for centre in &points[..40] {
            let in_front = |low: Vec2, high: Vec2| {
                [
                    low,
                    high,
                    Vec2::new(low.x, high.y),
                    Vec2::new(high.x, low.y),
                ]
                .iter()
                .any(|corner| forward.dot(*corner - *centre) >= 0.0)
            };
            let mut seen = vec![false; points.len()];
            let mut visited = 0;
            for &(first, end) in grid.runs_near(*centre, Some(forward)).as_slice() {
                for slot in first as usize..end as usize {
                    seen[grid.entries()[slot] as usize] = true;
                    visited += 1;
                    // Only cells that reach the half-plane (up to the rounding margin).
                    let (cx, cy) = grid.cell_of(grid.point(slot));
                    let low = grid.origin + Vec2::new(cx as f32, cy as f32) * grid.cell_size;
                    let slack = grid.rounding_margin(*centre) + 0.01;
                    assert!(in_front(
                        low - Vec2::splat(slack),
                        low + grid.cell_size + Vec2::splat(slack)
                    ));
                }
            }
            let mut all = 0;
            grid.for_each_near(*centre, |_, _| all += 1);
            assert!(visited <= all);
            (total_visited, total_all) = (total_visited + visited, total_all + all);
            for (i, point) in points.iter().enumerate() {
                let offset = *point - *centre;
                if offset.length() <= 10.0 && forward.dot(offset) >= 0.0 {
                    assert!(seen[i], "missed a point in front, facing {forward}");
                }
            }
        }
        (total_visited, total_all)
    }

    #[test]
    fn culled_queries_still_see_every_point_of_the_kept_half() {
        // Near the origin and far from it (where coordinates round coarsely), facing every
        // way, the axes included.
        let (mut total_visited, mut total_all) = (0, 0);
        for shift in [Vec2::ZERO, Vec2::new(4.0e4, -7.0e4)] {
            let (points, grid) = scattered(&mut Random::new(5), 400, Vec2::splat(30.0), shift, 400);
            for angle in [0.7f32, 0.0, 1.0, 2.0, 3.0, 4.0, 5.0, 6.0] {
                let forward = if angle.fract() == 0.0 {
                    // Exactly along an axis: one of the components is zero.
                    [Vec2::X, Vec2::Y, -Vec2::X, -Vec2::Y][angle as usize % 4]
                } else {
                    Vec2::from_angle(angle)
                };
                let (visited, all) = check_culled_query(&grid, &points, forward);
                (total_visited, total_all) = (total_visited + visited, total_all + all);
            }
        }
        // The half behind is mostly skipped.
        assert!(
            total_visited < total_all * 3 / 4,
            "{total_visited} of {total_all}"
        );
    }

    /// The runs clipped `W::LANES` rows at a time are those clipped one row at a time, for
    /// centres inside the grid, on its edges and outside it, facing every way or none.
    fn runs_at_width_equal_runs_one_row_at_a_time<W: Wide>() {
        let mut random = Random::new(9);
        let (points, grid) = scattered(&mut random, 300, Vec2::new(25.0, 40.0), Vec2::ZERO, 300);
        let aheads = [
            None,
            Some(Vec2::X),
            Some(-Vec2::Y),
            Some(Vec2::from_angle(2.2)),
        ];
        let outside: Vec<Vec2> = (0..100)
            .map(|_| Vec2::new(random.range(-60.0, 60.0), random.range(-80.0, 80.0)))
            .collect();
        for &centre in points.iter().chain(&outside) {
            for ahead in aheads {
                let (one, wide) = (
                    grid.runs_near(centre, ahead),
                    grid.runs_near_lanes::<W>(centre, ahead),
                );
                assert_eq!(one.as_slice(), wide.as_slice(), "{} lanes", W::LANES);
            }
        }
    }

    #[test]
    fn runs_are_the_same_at_every_width() {
        crate::math::wide::for_every_width!(runs_at_width_equal_runs_one_row_at_a_time());
    }
}
