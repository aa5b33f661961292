//! Radial density masking (seed 000 §4.4.2, after Vlachos, GDC 2016): in the scene pass, a
//! stencil mask skips 2×2 pixel quads in the periphery — every other quad past `inner`, three in
//! four past `outer`, distances in units of the lens ellipse — and a reconstruction pass fills the
//! skipped quads from their kept neighbours. Shaders: `radial_density.glsl`, `radial_mask.frag`,
//! `reconstruct.frag`; executor: `render/radial_density.rs`.

use glam::Vec4;

use super::model::*;
use super::output::sampling_pass;
use super::pipeline::{Constant, PipelineDesc, StepContext};
use super::steps::{stencil_placeholder, Step};
use super::{ConfigError, Resolution};
use crate::shaders::{
    COMPOSITE_VERT, RADIAL_MASK_FRAG, RADIAL_MASK_FRAG_COUNTING, RECONSTRUCT_FRAG,
    RECONSTRUCT_FRAG_COUNTING,
};
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

/// The mask's full-view draw writes stencil only.
pub(super) fn radial_mask_pipeline(ctx: &StepContext, r: &RadialDensityGeometry) -> PipelineDesc {
    let desc = ctx.pipeline(
        &COMPOSITE_VERT,
        &RADIAL_MASK_FRAG,
        &RADIAL_MASK_FRAG_COUNTING,
    );
    PipelineDesc {
        writes_colour: false,
        ..with_lens(desc, r)
    }
}

pub(super) fn reconstruct_pipeline(ctx: &StepContext, r: &RadialDensityGeometry) -> PipelineDesc {
    let desc = ctx.pipeline(
        &COMPOSITE_VERT,
        &RECONSTRUCT_FRAG,
        &RECONSTRUCT_FRAG_COUNTING,
    );
    with_lens(desc, r)
}

/// The view's size, the radii and each eye's lens ellipse (`shaders/radial_density.glsl`).
fn with_lens(desc: PipelineDesc, r: &RadialDensityGeometry) -> PipelineDesc {
    use Constant::*;
    let values = [
        r.view.width as f32,
        r.view.height as f32,
        r.config.inner,
        r.config.outer,
    ]
    .into_iter()
    .chain(r.lens.iter().flat_map(|l| l.to_array()));
    let names = [
        ViewWidth, ViewHeight, Inner, Outer, LeftCx, LeftCy, LeftRx, LeftRy, RightCx, RightCy,
        RightRx, RightRy,
    ];
    names
        .into_iter()
        .zip(values)
        .fold(desc, |desc, (name, value)| desc.float(name, value))
}
