//! Percentiles of a character's `S_max(t)`: exact (offline) and streaming (online).
//!
//! The attention threshold `A` is the `(100 − a)`th percentile of `S_max(t)`. Offline the
//! whole series is known and [`exact_quantile`] sorts it. Online, [`ScoreHistogram`] keeps
//! a fixed 64-bin histogram of the scores (normalised by `S_MAX`), from which any quantile
//! can be read in O(64) with no allocation — the level is not fixed in advance, which the
//! online tracker needs to correct for its reaction delay. The tracker reads it every
//! frame with [`ScoreHistogram::quantile_near`], which starts where the last answer was
//! (0.19 bins away on average in a moving crowd of 10 000, 0.02 at 1 000) and gives the
//! same value.

/// The `p`-quantile (`p` ∈ [0, 1]) of `values` by linear interpolation between order
/// statistics (the "type 7" rule of R and numpy). Sorts `values` in place. `None` if empty.
pub fn exact_quantile(values: &mut [f32], p: f32) -> Option<f32> {
    if values.is_empty() {
        return None;
    }
    values.sort_unstable_by(f32::total_cmp);
    let position = p.clamp(0.0, 1.0) * (values.len() - 1) as f32;
    let below = position.floor() as usize;
    let above = (below + 1).min(values.len() - 1);
    let fraction = position - below as f32;
    Some(values[below] + (values[above] - values[below]) * fraction)
}

/// Number of bins of [`ScoreHistogram`].
pub const HISTOGRAM_BINS: usize = 64;

/// A streaming estimate of the distribution of scores in [0, 1], to read any quantile:
/// 64 equal bins of 16-bit counts (128 bytes), no allocation. When a bin would overflow,
/// every count is halved, so very old samples slowly lose weight. Quantiles interpolate
/// linearly inside a bin (resolution 1/64 of the range).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ScoreHistogram {
    counts: [u16; HISTOGRAM_BINS],
    total: u32,
    /// The bin where [`quantile_near`](Self::quantile_near) last found its answer.
    cursor_bin: u32,
    /// Samples in the bins below `cursor_bin` (kept up to date by every push).
    cursor_below: u32,
}

impl Default for ScoreHistogram {
    fn default() -> Self {
        ScoreHistogram {
            counts: [0; HISTOGRAM_BINS],
            total: 0,
            cursor_bin: 0,
            cursor_below: 0,
        }
    }
}

impl ScoreHistogram {
    /// Number of samples currently weighing in the histogram.
    pub fn total(&self) -> u32 {
        self.total
    }

    /// Adds a sample; values are clamped to [0, 1], non-finite ones ignored.
    pub fn push(&mut self, value: f32) {
        if !value.is_finite() {
            return;
        }
        let bin =
            ((value.clamp(0.0, 1.0) * HISTOGRAM_BINS as f32) as usize).min(HISTOGRAM_BINS - 1);
        if self.counts[bin] == u16::MAX {
            self.total = 0;
            self.cursor_below = 0;
            for (index, count) in self.counts.iter_mut().enumerate() {
                *count /= 2;
                self.total += u32::from(*count);
                if index < self.cursor_bin as usize {
                    self.cursor_below += u32::from(*count);
                }
            }
        }
        self.counts[bin] += 1;
        self.total += 1;
        self.cursor_below += u32::from(bin < self.cursor_bin as usize);
    }

    /// The `level`-quantile (level in [0, 1]) of the samples, `None` if there are none.
    pub fn quantile(&self, level: f32) -> Option<f32> {
        if self.total == 0 {
            return None;
        }
        let target = level.clamp(0.0, 1.0) * self.total as f32;
        // The first non-empty bin whose cumulative count reaches `target`. Counts are whole
        // numbers below 2²⁴ (exact in f32), so that is the first bin whose cumulative count
        // reaches `needed`: found eight bins at a time, then bin by bin.
        let needed = ceil_to_u32(target).max(1);
        let mut below = 0u32;
        for (chunk_index, chunk) in self.counts.chunks_exact(8).enumerate() {
            let chunk_total: u32 = chunk.iter().map(|&count| u32::from(count)).sum();
            if below + chunk_total < needed {
                below += chunk_total;
                continue;
            }
            for (i, &count) in chunk.iter().enumerate() {
                let count = u32::from(count);
                if below + count >= needed {
                    return Some(value_in_bin(chunk_index * 8 + i, below, count, target));
                }
                below += count;
            }
        }
        Some(1.0)
    }

    /// [`quantile`](Self::quantile), searched from the bin of the last answer rather than
    /// from the first bin: the same value, found in a step or two when the level and the
    /// samples change little between calls (as they do frame to frame).
    pub fn quantile_near(&mut self, level: f32) -> Option<f32> {
        if self.total == 0 {
            return None;
        }
        let target = level.clamp(0.0, 1.0) * self.total as f32;
        // As in `quantile`: the first bin whose cumulative count reaches `needed`.
        let needed = ceil_to_u32(target).max(1);
        let (mut bin, mut below) = (self.cursor_bin as usize, self.cursor_below);
        // Down while the bins below already reach it (below ≥ needed ≥ 1, so bin > 0)...
        while below >= needed && bin > 0 {
            bin -= 1;
            below -= u32::from(self.counts[bin]);
        }
        // ...up while this bin does not.
        while bin < HISTOGRAM_BINS && below + u32::from(self.counts[bin]) < needed {
            below += u32::from(self.counts[bin]);
            bin += 1;
        }
        let Some(&count) = self.counts.get(bin) else {
            // No bin reaches it (as in `quantile`; the cursor stays where it was).
            return Some(1.0);
        };
        (self.cursor_bin, self.cursor_below) = (bin as u32, below);
        Some(value_in_bin(bin, below, u32::from(count), target))
    }
}

/// The normalised score at which the cumulative count reaches `target` inside bin `bin`,
/// which holds `count` samples above `below` ones: linear within the bin.
#[inline]
fn value_in_bin(bin: usize, below: u32, count: u32, target: f32) -> f32 {
    let inside = ((target - below as f32) / count as f32).clamp(0.0, 1.0);
    (bin as f32 + inside) / HISTOGRAM_BINS as f32
}

/// `⌈x⌉` for `x` in [0, 2³²) (no call to `ceilf`, which x86-64's baseline lacks).
fn ceil_to_u32(x: f32) -> u32 {
    let truncated = x as u32;
    if (truncated as f32) < x {
        truncated + 1
    } else {
        truncated
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::random::Random;

    #[test]
    fn exact_quantile_interpolates() {
        let mut values = [4.0, 1.0, 3.0, 2.0, 5.0];
        assert_eq!(exact_quantile(&mut values, 0.5), Some(3.0));
        assert_eq!(exact_quantile(&mut values, 0.0), Some(1.0));
        assert_eq!(exact_quantile(&mut values, 1.0), Some(5.0));
        assert_eq!(exact_quantile(&mut values, 0.625), Some(3.5));
        assert_eq!(exact_quantile(&mut [], 0.5), None);
    }

    #[test]
    fn histogram_tracks_the_exact_quantile() {
        for level in [0.3f32, 0.5, 0.7, 0.9] {
            let mut random = Random::new(11);
            let mut histogram = ScoreHistogram::default();
            let mut all = Vec::new();
            for _ in 0..100_000 {
                // A skewed mixture, like S_max: a spike at 0 and a spread above.
                let value = if random.next_f32() < 0.2 {
                    0.0
                } else {
                    random.next_f32().powi(2)
                };
                histogram.push(value);
                all.push(value);
            }
            let exact = exact_quantile(&mut all, level).unwrap();
            let estimate = histogram.quantile(level).unwrap();
            assert!(
                (estimate - exact).abs() < 0.02,
                "level {level}: {estimate} vs {exact}"
            );
        }
    }

    /// The quantile by the definition: interpolated in the first non-empty bin whose
    /// cumulative count reaches the target.
    fn quantile_by_definition(histogram: &ScoreHistogram, level: f32) -> Option<f32> {
        if histogram.total == 0 {
            return None;
        }
        let target = level.clamp(0.0, 1.0) * histogram.total as f32;
        let mut below = 0.0f32;
        for (bin, &count) in histogram.counts.iter().enumerate() {
            let count = f32::from(count);
            if count > 0.0 && below + count >= target {
                let inside = ((target - below) / count).clamp(0.0, 1.0);
                return Some((bin as f32 + inside) / HISTOGRAM_BINS as f32);
            }
            below += count;
        }
        Some(1.0)
    }

    #[test]
    fn quantile_equals_its_definition() {
        let mut random = Random::new(12);
        for round in 0..200 {
            let mut histogram = ScoreHistogram::default();
            // Sparse or dense, skewed: empty bins and whole empty chunks among them.
            let samples = 1 + round * 7;
            let power = 1.0 + (round % 5) as f32;
            for _ in 0..samples {
                histogram.push(random.range(0.0, 1.0).powf(power));
            }
            for step in 0..=100 {
                let level = step as f32 / 100.0;
                assert_eq!(
                    histogram.quantile(level),
                    quantile_by_definition(&histogram, level),
                    "round {round}, level {level}"
                );
            }
        }
        assert_eq!(ScoreHistogram::default().quantile(0.5), None);
    }

    /// `quantile_near` gives `quantile`'s value whatever came before: levels that wander
    /// and jump, samples pushed between the reads (above and below the cursor), and the
    /// halving of every count.
    #[test]
    fn quantile_near_equals_quantile() {
        let mut random = Random::new(13);
        let mut histogram = ScoreHistogram::default();
        assert_eq!(histogram.quantile_near(0.5), None);
        let mut level = 0.5f32;
        for read in 0..40_000 {
            let pushes = if read < 100 { 3 } else { random.below(3) };
            for _ in 0..pushes {
                let value = if read % 1_000 < 500 {
                    random.next_f32().powi(3)
                } else {
                    random.next_f32()
                };
                histogram.push(value);
            }
            if read % 4_000 == 3_999 {
                // Fill one bin to the top: every count halves.
                for _ in 0..u16::MAX {
                    histogram.push(0.3);
                }
            }
            level = if read % 97 == 0 {
                random.next_f32()
            } else {
                (level + random.range(-0.02, 0.02)).clamp(0.0, 1.0)
            };
            let expected = histogram.quantile(level);
            assert_eq!(histogram.quantile_near(level), expected, "read {read}");
        }
        assert_eq!(histogram.quantile_near(1.0), histogram.quantile(1.0));
        assert_eq!(histogram.quantile_near(0.0), histogram.quantile(0.0));
    }

    #[test]
    fn histogram_halves_instead_of_overflowing() {
        let mut histogram = ScoreHistogram::default();
        assert_eq!(histogram.quantile(0.5), None);
        for _ in 0..70_000 {
            histogram.push(0.5);
        }
        histogram.push(f32::NAN);
        histogram.push(2.0);
        assert!(histogram.total() < 70_000);
        let median = histogram.quantile(0.5).unwrap();
        assert!((0.5..0.52).contains(&median), "{median}");
        assert_eq!(histogram.quantile(1.0), Some(1.0));
    }
}
