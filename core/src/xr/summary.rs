//! What a run with the runtime measured: frames and pacing, the workload, the eyes' fit, the
//! HMD mask, the pixel check and the judgements.

use super::pixels::PixelCheck;
use super::visibility::MaskFractions;
use crate::judge::LiveJudgement;

/// The per-second line's extra: the runtime's frame timing.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Pacing {
    /// The runtime's predicted display period (ms), as last said.
    pub display_period_ms: f64,
    /// Frames whose display time came more than one period after the previous one's: the
    /// runtime skipped a display slot because the app was late.
    pub late: u64,
}

/// What a finished run measured.
#[derive(Clone, Debug, Default)]
pub struct XrSummary {
    /// Frames rendered (not counting those submitted empty).
    pub frames_rendered: u64,
    /// Frames the session keeps in flight: each recorded and submitted without waiting for
    /// the GPU, whose figures are read when its slot comes round again.
    pub frames_in_flight: usize,
    /// The runtime's frame timing.
    pub pacing: Pacing,
    /// Wall time of each rendered frame (the runtime's wait excluded: locate, record, submit;
    /// with frames in flight, the wait for the frame that held the slot before), ms.
    pub frame_ms: Vec<f64>,
    /// How often the runtime's views changed enough to plan the frame again.
    pub replans: u64,
    /// The last rendered frame's draw calls and triangles recorded (the workload beside the
    /// times).
    pub draws: (u64, u64),
    /// How far the runtime's eyes lay from foveate's eye model (largest over the run).
    pub eye_fit_error: (f32, f32),
    /// The first frame checked against a render of the same views, when asked for.
    pub pixels: Option<PixelCheck>,
    /// The HMD mask's hidden fractions, when it took the runtime's mesh.
    pub mask_hidden: Option<MaskFractions>,
    /// What `judge` measured.
    pub judged: Judged,
}

/// The judged frames of a run (`XrSettings::judge`).
#[derive(Clone, Debug, Default)]
pub struct Judged {
    /// Frames judged.
    pub frames: u64,
    /// The last judgement.
    pub last: Option<LiveJudgement>,
    /// Wall time judging, all frames together (ms): reading back, the reference, the judge.
    pub ms: f64,
}
