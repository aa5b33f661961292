//! Summaries of per-pixel error maps.

/// What an error map says: its mean and upper percentiles over the pixels it covers.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ErrorSummary {
    /// The mean.
    pub mean: f64,
    /// The 95th percentile.
    pub p95: f64,
    /// The 99th percentile.
    pub p99: f64,
    /// Pixels summarised.
    pub pixels: usize,
}

impl ErrorSummary {
    /// `None` for no pixels. The percentiles are order statistics (the value at rank
    /// round((n − 1) q)), selected rather than sorted: a panel's millions of pixels in linear
    /// time.
    pub fn of(values: &[f32]) -> Option<ErrorSummary> {
        if values.is_empty() {
            return None;
        }
        let mean = values.iter().map(|&x| x as f64).sum::<f64>() / values.len() as f64;
        let mut v: Vec<f32> = values.to_vec();
        let rank = |q: f64| ((v.len() - 1) as f64 * q).round() as usize;
        let (r95, r99) = (rank(0.95), rank(0.99));
        let (below, p99, _) = v.select_nth_unstable_by(r99, f32::total_cmp);
        let p99 = *p99 as f64;
        // Everything below rank r99 is no larger than it: rank r95 lies among those.
        let p95 = if r95 < r99 {
            *below.select_nth_unstable_by(r95, f32::total_cmp).1 as f64
        } else {
            p99
        };
        Some(ErrorSummary {
            mean,
            p95,
            p99,
            pixels: values.len(),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The selected percentiles are the sorted values at their ranks, ties and repeats included.
    /// Mutations: rank n·q instead of (n − 1)·q, or p95 selected above p99's rank, each fail.
    #[test]
    fn percentiles_are_the_sorted_values_at_their_ranks() {
        let mut state = 12345u32;
        for len in [1usize, 2, 19, 20, 21, 100, 1001] {
            let values: Vec<f32> = (0..len)
                .map(|_| {
                    state = state.wrapping_mul(1664525).wrapping_add(1013904223);
                    (state >> 24) as f32 / 16.0
                })
                .collect();
            let mut sorted = values.clone();
            sorted.sort_by(f32::total_cmp);
            let at = |q: f64| sorted[((len - 1) as f64 * q).round() as usize] as f64;
            let s = ErrorSummary::of(&values).unwrap();
            assert_eq!((s.p95, s.p99, s.pixels), (at(0.95), at(0.99), len));
            let mean = values.iter().map(|&v| v as f64).sum::<f64>() / len as f64;
            assert!((s.mean - mean).abs() < 1e-12);
        }
        assert_eq!(ErrorSummary::of(&[]), None);
    }
}
