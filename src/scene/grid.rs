//! A uniform grid over the ground plane, rebuilt every frame without allocation.
//!
//! Each rebuild fits the grid to the points' bounding box with square cells of side
//! `radius / 2` (larger if the box would need more cells than the grid has room for), and
//! counting-sorts the points by cell, row by row. A query of the grid's radius then reads
//! the 5 × 5 cells around a point as five contiguous runs of the sorted points — no hashing,
//! no duplicates, and sequential memory. (25 cells of (r/2)² cover 6.25 r², against 9 r²
//! for 3 × 3 cells of side r.)

use glam::Vec2;

/// Extra coordinates after the last slot, so that a query may read four slots at a time
/// from any slot without running off the arrays (what it reads there, it masks off).
pub const SLOT_PADDING: usize = 3;

/// The grid: `cell_start[c] .. cell_start[c + 1]` indexes `entries`, `xs` and `ys` for
/// cell `c`.
#[derive(Debug, Clone)]
pub struct SpatialGrid {
    radius: f32,
    cell_size: f32,
    inverse_cell_size: f32,
    origin: Vec2,
    columns: i32,
    rows: i32,
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
    /// A grid for at most `capacity` points, answering queries of radius `radius` (metres).
    pub fn new(capacity: usize, radius: f32) -> SpatialGrid {
        let max_cells = (capacity.max(1) * 4).max(64);
        SpatialGrid {
            radius,
            cell_size: radius / 2.0,
            inverse_cell_size: 2.0 / radius,
            origin: Vec2::ZERO,
            columns: 1,
            rows: 1,
            max_cells,
            cell_start: vec![0; max_cells + 1],
            entries: vec![0; capacity],
            xs: vec![0.0; capacity + SLOT_PADDING],
            ys: vec![0.0; capacity + SLOT_PADDING],
            len: 0,
        }
    }

    /// Side of a cell in metres (half the query radius, or more for a sprawling scene).
    pub fn cell_size(&self) -> f32 {
        self.cell_size
    }

    #[inline]
    fn cell_of(&self, point: Vec2) -> (i32, i32) {
        let scaled = (point - self.origin) * self.inverse_cell_size;
        // Saturating float → int casts keep far-away points valid.
        (scaled.x.floor() as i32, scaled.y.floor() as i32)
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
        // Cells of radius/2, grown until the bounding box fits in max_cells. A box wider
        // than a float holds (points near ±f32::MAX) counts as f32::MAX wide, or the
        // doubling below would never end.
        let extent = (high - low).max(Vec2::ZERO).min(Vec2::splat(f32::MAX));
        let mut cell_size = self.radius / 2.0;
        loop {
            let columns = (extent.x / cell_size).floor() as f64 + 1.0;
            let rows = (extent.y / cell_size).floor() as f64 + 1.0;
            if columns * rows <= self.max_cells as f64 {
                self.columns = columns as i32;
                self.rows = rows as i32;
                break;
            }
            cell_size *= 2.0;
        }
        self.cell_size = cell_size;
        self.inverse_cell_size = 1.0 / cell_size;
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
    /// point of the 5 × 5 cells around `centre` — a superset of the points within the
    /// grid's radius of it. Each slot comes once.
    #[inline]
    pub fn for_each_run_near(&self, centre: Vec2, visit: impl FnMut(std::ops::Range<usize>)) {
        self.for_each_run_near_where(centre, |_, _| true, visit);
    }

    /// Like [`for_each_run_near`](Self::for_each_run_near), but only over the cells for
    /// which `keep_cell(lowest corner, highest corner)` is true (adjacent kept cells of a
    /// row still come as one run).
    #[inline]
    pub fn for_each_run_near_where(
        &self,
        centre: Vec2,
        keep_cell: impl Fn(Vec2, Vec2) -> bool,
        mut visit: impl FnMut(std::ops::Range<usize>),
    ) {
        let span = (self.radius * self.inverse_cell_size).ceil() as i32;
        let (cx, cy) = self.cell_of(centre);
        let first_column = cx.saturating_sub(span).max(0);
        let last_column = cx.saturating_add(span).min(self.columns - 1);
        if first_column > last_column {
            return;
        }
        let first_row = cy.saturating_sub(span).max(0);
        let last_row = cy.saturating_add(span).min(self.rows - 1);
        let size = self.cell_size;
        for row in first_row..=last_row {
            let low_y = self.origin.y + row as f32 * size;
            let mut run_start: Option<i32> = None;
            for column in first_column..=last_column + 1 {
                let kept = column <= last_column && {
                    let low = Vec2::new(self.origin.x + column as f32 * size, low_y);
                    keep_cell(low, low + Vec2::splat(size))
                };
                match (kept, run_start) {
                    (true, None) => run_start = Some(column),
                    (false, Some(start)) => {
                        let first = self.cell_start[(row * self.columns + start) as usize];
                        let end = self.cell_start[(row * self.columns + column - 1) as usize + 1];
                        visit(first as usize..end as usize);
                        run_start = None;
                    }
                    _ => {}
                }
            }
        }
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

    #[test]
    fn finds_every_point_within_the_radius_exactly_once() {
        let mut random = Random::new(3);
        let points: Vec<Vec2> = (0..500)
            .map(|_| Vec2::new(random.range(-60.0, 60.0), random.range(-60.0, 60.0)))
            .collect();
        let mut grid = SpatialGrid::new(600, 10.0);
        grid.rebuild(&points);
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
    fn sprawling_scenes_grow_the_cells_instead_of_the_memory() {
        let points = [
            Vec2::new(-1e6, 1e6),
            Vec2::new(1e6, -1e6),
            Vec2::ZERO,
            Vec2::new(3.0, 4.0),
        ];
        let mut grid = SpatialGrid::new(4, 10.0);
        grid.rebuild(&points);
        assert!(grid.cell_size() > 5.0);
        let mut near = Vec::new();
        grid.for_each_near(Vec2::ZERO, |i, _| near.push(i));
        assert!(near.contains(&2) && near.contains(&3));
        grid.rebuild(&[]);
        grid.for_each_near(Vec2::ZERO, |_, _| panic!("empty grid"));
    }

    #[test]
    fn culled_queries_still_see_every_point_of_the_kept_half() {
        let mut random = Random::new(5);
        let points: Vec<Vec2> = (0..400)
            .map(|_| Vec2::new(random.range(-30.0, 30.0), random.range(-30.0, 30.0)))
            .collect();
        let mut grid = SpatialGrid::new(400, 10.0);
        grid.rebuild(&points);
        let forward = Vec2::from_angle(0.7);
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
            grid.for_each_run_near_where(*centre, in_front, |run| {
                for slot in run {
                    seen[grid.entries()[slot] as usize] = true;
                    visited += 1;
                }
            });
            let mut all = 0;
            grid.for_each_near(*centre, |_, _| all += 1);
            assert!(visited <= all);
            for (i, point) in points.iter().enumerate() {
                let offset = *point - *centre;
                if offset.length() <= 10.0 && forward.dot(offset) >= 0.0 {
                    assert!(seen[i], "missed a point in front");
                }
            }
        }
    }
}
