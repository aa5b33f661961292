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
    /// `None` for no pixels.
    pub fn of(values: &[f32]) -> Option<ErrorSummary> {
        if values.is_empty() {
            return None;
        }
        let mut v: Vec<f32> = values.to_vec();
        v.sort_by(f32::total_cmp);
        let at = |q: f64| v[((v.len() - 1) as f64 * q).round() as usize] as f64;
        Some(ErrorSummary {
            mean: v.iter().map(|&x| x as f64).sum::<f64>() / v.len() as f64,
            p95: at(0.95),
            p99: at(0.99),
            pixels: v.len(),
        })
    }
}
