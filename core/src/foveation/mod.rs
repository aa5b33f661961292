//! Foveation maths that needs no GPU (Arm's white paper, Di Donato 2017 §3): the inset field of view,
//! where the fovea views look for a gaze, the analytic pixel budget of Tables 2–4, and gaze
//! input that never panics on bad samples, a simulated eye, and the tracker's latency.

mod budget;
mod config;
mod eye_movement;
mod gaze;
mod history;
mod inset;
mod latency;
mod ring;
mod temporal;
mod views;

pub use budget::PixelBudget;
internal_use!(budget::{arm_table, ArmRow, ARM_PI, ARM_TABLE4_FOVEA});
pub use config::{
    FoveationConfig, FoveationGeometry, PeripheryFilter, ACCUMULATED_REACH_PX, FOVEA_REACH_TEXELS,
    PERIPHERY_REACH_TEXELS, RECOMMENDED_PERIPHERY_DENSITY,
};
pub use eye_movement::{
    amplitude_for_peak_velocity, large_saccade_trace, saccade_duration_s, saccade_peak_velocity,
    EyeMovementModel, EyeTrace, GazeSpace, SaccadeEvent, SeededRng, TRUTH_HZ,
};
pub use gaze::{check_gaze, parse_gaze_csv, simulated_trace, GazeError, GazeFilter, GazeSample};
pub use history::{HistoryAt, HistoryFormat};
pub use inset::{fovea_tangents, inset_fov_deg};
pub use latency::{
    detect_saccades, DelayedGaze, GazeLatency, Prediction, MAX_LATENCY_MS, SACCADE_THRESHOLD_DEG_S,
};
pub use ring::RingGeometry;
pub use temporal::{
    halton, ClipNeighbourhood, HistoryClip, HistoryFilter, NewSample, TemporalConfig,
    REACH_EDGE_DEG,
};
pub use views::{fovea_centre_px, fovea_views, gaze_tangent, mask_shapes, ring_views, MASK_SHAPES};
