//! The runtime's visibility mask (`XR_KHR_visibility_mask`): each eye's hidden-area mesh, and
//! how much of each eye the HMD mask hides with it.

use glam::Vec2;
use openxr as xr;

use super::error::{XrError, XrResultExt};
use super::runtime::STEREO;
use crate::view::HiddenArea;

/// Each eye's hidden-area mesh (`XR_KHR_visibility_mask`).
pub(super) fn hidden_areas(session: &xr::Session<xr::Vulkan>) -> Result<[HiddenArea; 2], XrError> {
    let area = |view: u32| {
        let mask = session
            .get_visibility_mask_khr(
                STEREO,
                view,
                xr::VisibilityMaskTypeKHR::HIDDEN_TRIANGLE_MESH,
            )
            .xr("xrGetVisibilityMaskKHR")?;
        let vertices: Vec<Vec2> = mask.vertices.iter().map(|v| Vec2::new(v.x, v.y)).collect();
        HiddenArea::from_indexed(&vertices, &mask.indices).map_err(XrError::Mask)
    };
    Ok([area(0)?, area(1)?])
}

/// How much of each eye the HMD mask hides: the runtime's mesh against the profile's figures.
#[derive(Clone, Copy, Debug)]
pub struct MaskFractions {
    /// Each eye's fraction under the runtime's mesh (its area, clipped to the view).
    pub mesh: [f64; 2],
    /// Each eye's fraction under the profile's fitted ellipse, at the runtime's field.
    pub ellipse: [f64; 2],
    /// The profile's published fraction, if it has one.
    pub published: Option<f32>,
    /// The profile the fractions are the figures of.
    pub profile: &'static str,
}
