//! Error histograms: what a judge reduces a per-pixel error map to, so that a frame's figures
//! need a few hundred kilobytes instead of the whole map. The GPU judge fills the same bins
//! with atomics (`shaders/flip_histogram.comp` bins exactly as [`ErrorHistogram::bin`]), so the
//! CPU oracle's and the GPU's figures are reduced alike.

use super::ErrorSummary;

/// Bins over (0, 1]; one more bin holds the errors of exactly 0.
pub const HISTOGRAM_BINS: usize = 1 << 14;

/// Counts of error values (0 … 1) in [`HISTOGRAM_BINS`] equal bins over (0, 1], and one for
/// exact zeros (an identical pixel). A summary read from it is exact in its pixel count and
/// within half a bin (1/32768) of the exact mean and percentiles; zero errors stay exactly 0.
/// Values above 1 count as 1; values that are not finite are not counted.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ErrorHistogram {
    counts: Vec<u64>,
}

impl Default for ErrorHistogram {
    fn default() -> Self {
        ErrorHistogram {
            counts: vec![0; HISTOGRAM_BINS + 1],
        }
    }
}

impl ErrorHistogram {
    /// The bin value `v` falls in: 0 for `v ≤ 0`, else 1 + ⌊v · bins⌋, the last for `v ≥ 1`.
    pub fn bin(v: f32) -> usize {
        if v <= 0.0 {
            0
        } else {
            1 + ((v * HISTOGRAM_BINS as f32) as usize).min(HISTOGRAM_BINS - 1)
        }
    }

    /// The value a bin stands for: 0 for the zero bin, else the bin's middle.
    fn value(bin: usize) -> f64 {
        if bin == 0 {
            0.0
        } else {
            (bin as f64 - 0.5) / HISTOGRAM_BINS as f64
        }
    }

    /// A histogram of `values` (those not finite left out).
    pub fn of(values: impl IntoIterator<Item = f32>) -> Self {
        let mut h = ErrorHistogram::default();
        values.into_iter().for_each(|v| h.add(v));
        h
    }

    /// Counts `v` (not at all if it is not finite).
    pub fn add(&mut self, v: f32) {
        if v.is_finite() {
            self.counts[Self::bin(v)] += 1;
        }
    }

    /// Adds another histogram's counts (another eye, another frame).
    pub fn merge(&mut self, other: &ErrorHistogram) {
        for (a, b) in self.counts.iter_mut().zip(&other.counts) {
            *a += b;
        }
    }

    /// A histogram from counts per bin, as the GPU judge reads them back
    /// (`HISTOGRAM_BINS + 1` of them, the zero bin first).
    pub(crate) fn from_counts(counts: &[u32]) -> Self {
        debug_assert_eq!(counts.len(), HISTOGRAM_BINS + 1);
        ErrorHistogram {
            counts: counts.iter().map(|&c| c as u64).collect(),
        }
    }

    /// Values counted.
    pub fn pixels(&self) -> u64 {
        self.counts.iter().sum()
    }

    /// The mean and percentiles (order statistics at rank round((n − 1) q), as
    /// [`ErrorSummary::of`]), each bin standing for its middle; `None` for no values.
    pub fn summary(&self) -> Option<ErrorSummary> {
        let n = self.pixels();
        if n == 0 {
            return None;
        }
        let sum: f64 = (self.counts.iter().enumerate())
            .map(|(bin, &c)| c as f64 * Self::value(bin))
            .sum();
        let at_rank = |q: f64| {
            let rank = ((n - 1) as f64 * q).round() as u64;
            let mut below = 0;
            for (bin, &c) in self.counts.iter().enumerate() {
                below += c;
                if below > rank {
                    return Self::value(bin);
                }
            }
            unreachable!("rank {rank} lies below the count {n}")
        };
        Some(ErrorSummary {
            mean: sum / n as f64,
            p95: at_rank(0.95),
            p99: at_rank(0.99),
            pixels: n as usize,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The histogram's summary lies within half a bin of the exact one, zeros stay exactly
    /// zero, and what is not finite is left out. Mutations: a bin's value at its edge instead
    /// of its middle, or the rank counted from 1, each fail.
    #[test]
    fn summaries_lie_within_half_a_bin_of_the_exact_ones() {
        let mut state = 987654321u32;
        let half_bin = 0.5 / HISTOGRAM_BINS as f64 + 1e-9;
        for len in [1usize, 2, 7, 100, 1001, 100_000] {
            let values: Vec<f32> = (0..len)
                .map(|i| {
                    state = state.wrapping_mul(1664525).wrapping_add(1013904223);
                    // A third exact zeros, the rest spread as FLIP's errors are: mostly small.
                    if i % 3 == 0 {
                        0.0
                    } else {
                        ((state >> 8) as f32 / (1u32 << 24) as f32).powi(3)
                    }
                })
                .collect();
            let exact = ErrorSummary::of(&values).unwrap();
            let h = ErrorHistogram::of(values.iter().copied());
            let s = h.summary().unwrap();
            assert_eq!(s.pixels, len);
            for (a, b) in [(s.mean, exact.mean), (s.p95, exact.p95), (s.p99, exact.p99)] {
                assert!((a - b).abs() <= half_bin, "{len}: {s:?} against {exact:?}");
            }
        }
        let zeros = ErrorHistogram::of([0.0; 10]).summary().unwrap();
        assert_eq!((zeros.mean, zeros.p99), (0.0, 0.0));
        let h = ErrorHistogram::of([f32::NAN, f32::INFINITY, 2.0]);
        assert_eq!(h.pixels(), 1);
        assert_eq!(ErrorHistogram::bin(2.0), HISTOGRAM_BINS);
        assert_eq!(ErrorHistogram::default().summary(), None);
        let mut both = ErrorHistogram::of([0.5]);
        both.merge(&ErrorHistogram::of([0.25, 0.0]));
        assert_eq!(both.pixels(), 3);
    }
}
