//! Stereo view culling on the CPU: bounds, frusta and cones, the stereo strategies (per-eye,
//! superfrustum, dual cone, round robin), batch tests over structure-of-arrays bounds, and a
//! chunk-grid + octree hierarchy traversed in parallel. No Vulkan here.
//!
//! Every fast `f32` test is conservative — it never rejects an object that touches the volume —
//! and is checked against slow `f64` oracles by property tests over the hard cases.

mod batch;
mod bounds;
mod cone;
mod frustum;
mod hierarchy;
internal_mod!(oracle);
mod stereo;
mod triangle;

internal_use!(batch::{batch_kernel, BatchError, SphereSoa});
pub use bounds::{Aabb, Relation, Sphere};
pub use cone::{Cone, ConeView, EllipticalCone};
pub use frustum::Frustum;
pub use hierarchy::{CullHierarchy, CullResult, CullStats, HierarchyParams, VisibleSet};
pub use stereo::{
    CullView, DualCone, PerEye, RoundRobin, StereoCull, StereoFrusta, Strategy, Superfrustum,
};
pub use triangle::Triangle;

/// Slack added to a radius so that `f32` rounding in a test on coordinates of magnitude `m`
/// can never turn a touching object into a rejected one. Relative error of a few dot
/// products is below 8 ulp of the largest magnitude involved; 32 leaves margin. Callers pass
/// the L1 norm of the relative position (an upper bound of the largest component that is
/// cheaper than a max in the vectorised kernels).
#[inline(always)]
pub(crate) fn rounding_slack(magnitude: f32) -> f32 {
    32.0 * f32::EPSILON * magnitude
}

#[cfg(test)]
mod hard_cases_tests;
#[cfg(test)]
mod tests;
