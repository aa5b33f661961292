//! Radial density masking (seed 000 §4.4.2, after Vlachos, GDC 2016): in the scene pass, a
//! stencil mask skips 2×2 pixel quads in the periphery — every other quad past `inner`, three in
//! four past `outer`, distances in units of the lens ellipse — and a reconstruction pass fills the
//! skipped quads from their kept neighbours. Shaders: `radial_density.glsl`, `radial_mask.frag`,
//! `reconstruct.frag`; executor: `render/radial_density.rs`.

use glam::Vec4;

use super::model::*;
use super::output::sampling_pass;
use super::steps::{stencil_placeholder, Step};
use super::{ConfigError, Resolution};
use crate::view::{Eye, EyeParams, HmdProfile};

/// What a user chooses.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RadialDensity {
    /// Inside this radius (1 = the lens edge) every quad is shaded.
    pub inner: f32,
    /// Past this radius three quads in four are skipped; between the two, every other one.
    pub outer: f32,
}

impl Default for RadialDensity {
    fn default() -> Self {
        RadialDensity {
            inner: 0.5,
            outer: 0.8,
        }
    }
}

/// Radial density masking as planned: the configuration and each eye's lens ellipse in NDC.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RadialDensityGeometry {
    pub config: RadialDensity,
    /// Centre x, y and radius x, y per eye.
    pub lens: [Vec4; 2],
    pub view: Resolution,
}

impl RadialDensity {
    pub(super) fn resolve(
        &self,
        hmd: &HmdProfile,
        eyes: &EyeParams,
        view: Resolution,
    ) -> Result<RadialDensityGeometry, ConfigError> {
        let ok = |r: f32| r.is_finite() && r >= 0.0;
        if !(ok(self.inner) && ok(self.outer) && self.inner < self.outer) {
            return Err(ConfigError::new(
                "radial_density",
                format!("inner {}, outer {}", self.inner, self.outer),
                "finite radii with 0 ≤ inner < outer (1 = the lens edge)",
            ));
        }
        Ok(RadialDensityGeometry {
            config: *self,
            lens: Eye::BOTH.map(|e| hmd.lens_region(eyes.fov(e)).ndc_ellipse()),
            view,
        })
    }
}

/// Adds the mask step to the scene pass — after any mask fans, before the scene; the scene and
/// probe skip what it marks (`steps::assign_stencil_states`) — then the reconstruction pass.
pub(super) fn add_radial_density(
    passes: &mut Vec<PassPlan>,
    attachments: &mut Vec<AttachmentPlan>,
    eye: Resolution,
) {
    let Some(scene) = passes.iter_mut().find(|p| p.kind == PassKind::Scene) else {
        return;
    };
    let at = scene
        .steps
        .iter()
        .position(|s| !matches!(s, Step::MaskFans { .. }))
        .unwrap_or(0);
    scene.steps.insert(
        at,
        Step::RadialMask {
            stencil: stencil_placeholder(),
        },
    );
    let scene = scene.clone();
    let views = scene.resolve.unwrap_or(scene.color).attachment;
    attachments[views].name = "masked stereo colour";
    let reconstruct = sampling_pass(
        vec![views],
        eye,
        attachments,
        "reconstruct (radial density)",
        PassKind::Reconstruct,
        Step::Reconstruct,
    );
    passes.push(reconstruct);
}
