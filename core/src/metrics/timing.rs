/// Summary statistics of a series of measurements (times in whatever unit they came in).
/// An empty series' summary (`Default`) is all zeros.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Stats {
    /// Measurements.
    pub count: usize,
    /// The median.
    pub median: f64,
    /// The mean.
    pub mean: f64,
    /// The 95th percentile.
    pub p95: f64,
    /// The least.
    pub min: f64,
    /// The greatest.
    pub max: f64,
}

impl Stats {
    /// `None` for an empty series. NaNs are ignored.
    pub fn of(samples: &[f64]) -> Option<Stats> {
        let mut v: Vec<f64> = samples.iter().copied().filter(|x| !x.is_nan()).collect();
        if v.is_empty() {
            return None;
        }
        v.sort_by(f64::total_cmp);
        let n = v.len();
        let median = if n % 2 == 1 {
            v[n / 2]
        } else {
            0.5 * (v[n / 2 - 1] + v[n / 2])
        };
        // Nearest-rank percentile.
        let p95 = v[((0.95 * n as f64).ceil() as usize).clamp(1, n) - 1];
        Some(Stats {
            count: n,
            median,
            mean: v.iter().sum::<f64>() / n as f64,
            p95,
            min: v[0],
            max: v[n - 1],
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn median_mean_p95() {
        let s = Stats::of(&[5.0, 1.0, 3.0, 2.0, 4.0]).unwrap();
        assert_eq!(
            (s.median, s.mean, s.min, s.max, s.p95),
            (3.0, 3.0, 1.0, 5.0, 5.0)
        );
        let even = Stats::of(&[1.0, 2.0, 3.0, 4.0]).unwrap();
        assert_eq!(even.median, 2.5);
        let many: Vec<f64> = (1..=100).map(f64::from).collect();
        assert_eq!(Stats::of(&many).unwrap().p95, 95.0);
        assert!(Stats::of(&[]).is_none());
        assert_eq!(Stats::of(&[f64::NAN, 2.0]).unwrap().count, 1);
    }
}
