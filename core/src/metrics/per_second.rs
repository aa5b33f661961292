//! Frame times gathered over about a second and summarised as medians: what a running window
//! (`foveate view`, the Android demo) reports once a second.

use std::time::{Duration, Instant};

use super::Stats;

/// The frames of the current second.
#[derive(Debug)]
pub struct PerSecond {
    start: Instant,
    frame_ms: Vec<f64>,
    gpu_pass_ms: Vec<Vec<f64>>,
}

/// One second's medians.
#[derive(Clone, Debug, PartialEq)]
pub struct SecondSummary {
    /// Frames in the second.
    pub frames: usize,
    /// Median wall time per frame (render and present).
    pub frame_ms: f64,
    /// Each pass's median GPU time, in plan order (empty when the frames had no timestamps).
    pub gpu_pass_ms: Vec<f64>,
}

impl Default for PerSecond {
    fn default() -> Self {
        PerSecond {
            start: Instant::now(),
            frame_ms: Vec::new(),
            gpu_pass_ms: Vec::new(),
        }
    }
}

impl PerSecond {
    /// A frame that took `frame_ms`, its passes `gpu_pass_ms` on the GPU.
    pub fn push(&mut self, frame_ms: f64, gpu_pass_ms: Vec<f64>) {
        self.frame_ms.push(frame_ms);
        self.gpu_pass_ms.push(gpu_pass_ms);
    }

    /// Whether a second has passed since this one began.
    pub fn due(&self) -> bool {
        self.start.elapsed() >= Duration::from_secs(1)
    }

    /// The medians so far (`None` without a frame), and a new second begins.
    pub fn take(&mut self) -> Option<SecondSummary> {
        let second = std::mem::take(self);
        let median = |v: &[f64]| Stats::of(v).map_or(0.0, |s| s.median);
        let passes = second.gpu_pass_ms.iter().map(Vec::len).max().unwrap_or(0);
        // A pass's median over the frames that timed it.
        let gpu_pass_ms = (0..passes)
            .map(|i| {
                let times: Vec<f64> = second
                    .gpu_pass_ms
                    .iter()
                    .filter_map(|frame| frame.get(i).copied())
                    .collect();
                median(&times)
            })
            .collect();
        (!second.frame_ms.is_empty()).then(|| SecondSummary {
            frames: second.frame_ms.len(),
            frame_ms: median(&second.frame_ms),
            gpu_pass_ms,
        })
    }
}

impl SecondSummary {
    /// The passes' medians summed.
    pub fn gpu_ms(&self) -> f64 {
        self.gpu_pass_ms.iter().sum()
    }

    /// "12.3 ms/frame (81 frames), GPU 10.1 ms [periphery 4.0, fovea 5.0, output 1.1]", with
    /// the passes named in plan order.
    pub fn describe(&self, pass_names: &[&str]) -> String {
        let passes = pass_names
            .iter()
            .zip(&self.gpu_pass_ms)
            .map(|(n, ms)| format!("{n} {ms:.1}"))
            .collect::<Vec<_>>()
            .join(", ");
        format!(
            "{:.1} ms/frame ({} frames), GPU {:.1} ms [{passes}]",
            self.frame_ms,
            self.frames,
            self.gpu_ms()
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn medians_per_pass_over_the_frames_that_timed_it() {
        let mut s = PerSecond::default();
        assert_eq!(s.take(), None, "no frame, no summary");
        // Medians differ from means here, and the last frame timed only its first pass.
        s.push(10.0, vec![4.0, 5.0]);
        s.push(50.0, vec![9.0, 7.0]);
        s.push(20.0, vec![5.0, 30.0]);
        s.push(30.0, vec![6.0]);
        let summary = s.take().expect("frames");
        assert_eq!(summary.frames, 4);
        assert_eq!(summary.frame_ms, 25.0);
        assert_eq!(summary.gpu_pass_ms, vec![5.5, 7.0]);
        assert_eq!(summary.gpu_ms(), 12.5);
        assert_eq!(
            summary.describe(&["periphery", "fovea"]),
            "25.0 ms/frame (4 frames), GPU 12.5 ms [periphery 5.5, fovea 7.0]"
        );
        assert_eq!(s.take(), None, "taking starts a new second");
        assert!(!s.due());
    }
}
