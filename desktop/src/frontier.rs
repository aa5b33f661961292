//! Choosing among measured configurations by time and error: the Pareto frontier, the most
//! accurate within a time budget (iso-time) and the cheapest within an error budget
//! (iso-error). Every command that recommends or plots a frontier chooses through here.

/// One measured configuration: its frame time (any unit, the same for all) and its error
/// (lower is better: the eccentricity-aware FLIP's 99th percentile).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Point {
    pub time: f64,
    pub error: f64,
}

/// The indices of the points no other point beats on both time and error, fastest first (of
/// equal points, the first).
pub fn pareto_frontier(points: &[Point]) -> Vec<usize> {
    let mut order: Vec<usize> = (0..points.len())
        .filter(|&i| points[i].time.is_finite() && points[i].error.is_finite())
        .collect();
    order.sort_by(|&a, &b| {
        let (p, q) = (points[a], points[b]);
        p.time.total_cmp(&q.time).then(p.error.total_cmp(&q.error))
    });
    let mut best = f64::INFINITY;
    order.retain(|&i| {
        let keep = points[i].error < best;
        best = best.min(points[i].error);
        keep
    });
    order
}

/// The cheapest point whose error is within `budget` (inclusive; the first of equally cheap).
pub fn cheapest_within_error(points: &[Point], budget: f64) -> Option<usize> {
    (0..points.len())
        .filter(|&i| points[i].error <= budget && points[i].time.is_finite())
        .min_by(|&a, &b| points[a].time.total_cmp(&points[b].time))
}

/// The most accurate point whose time is within `budget` (inclusive; the first of equally
/// accurate).
pub fn most_accurate_within_time(points: &[Point], budget: f64) -> Option<usize> {
    (0..points.len())
        .filter(|&i| points[i].time <= budget && points[i].error.is_finite())
        .min_by(|&a, &b| points[a].error.total_cmp(&points[b].error))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn table() -> Vec<Point> {
        [
            (100.0, 0.0), // 0 reference
            (60.0, 0.30), // 1 stereo, MSAA 1
            (70.0, 0.12), // 2 foveated 0.5
            (50.0, 0.25), // 3 foveated 0.35
            (40.0, 0.41), // 4 foveated 0.25
            (55.0, 0.25), // 5 beaten by 3 on time, equal error
            (45.0, f64::NAN),
        ]
        .map(|(time, error)| Point { time, error })
        .to_vec()
    }

    /// The frontier keeps the points nothing beats on both, fastest first. Mutation: keeping
    /// by `<=` (5 joins) or by "higher is better" fails it.
    #[test]
    fn the_frontier_keeps_only_unbeaten_points() {
        assert_eq!(pareto_frontier(&table()), vec![4, 3, 2, 0]);
    }

    /// Iso-error picks the cheapest within the budget (inclusive), iso-time the most accurate
    /// within the time. Mutation: an exclusive budget, or iso-time picking the cheapest, fails.
    #[test]
    fn iso_error_and_iso_time_pick_from_the_table() {
        let t = table();
        assert_eq!(cheapest_within_error(&t, 0.26), Some(3));
        assert_eq!(cheapest_within_error(&t, 0.25), Some(3), "inclusive");
        assert_eq!(cheapest_within_error(&t, 0.2), Some(2));
        assert_eq!(cheapest_within_error(&t, 0.5), Some(4));
        assert_eq!(cheapest_within_error(&t, 0.05), Some(0));
        assert_eq!(cheapest_within_error(&t[1..], 0.05), None);
        assert_eq!(most_accurate_within_time(&t, 65.0), Some(3));
        assert_eq!(most_accurate_within_time(&t, 70.0), Some(2), "inclusive");
        assert_eq!(
            most_accurate_within_time(&t, 45.0),
            Some(4),
            "NaN error skipped"
        );
        assert_eq!(most_accurate_within_time(&t, 30.0), None);
    }
}
