//! Monoscopic far-field rendering (Preißner 2020 §4.3): the near field in stereo, the far field once
//! from one viewpoint, composited into each eye by reprojection.
//!
//! The maths here needs no GPU: the split distance from a disparity threshold, the one far
//! projection that covers both eyes' far frusta (canted and asymmetric eyes included), and the
//! per-view reprojection the composite shader evaluates.

mod config;
mod geometry;

pub use config::{MffrConfig, MffrOrder, MffrVariant, SplitDistance, FAR_DENSITY_RANGE};
pub use geometry::{
    far_view_from_head, split_for_disparity, FarReprojection, MffrGeometry, FAR_VIEW_INDEX,
};
