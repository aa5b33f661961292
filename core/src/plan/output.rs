//! The output stage: every frame's last pass when it has one, writing what the display shows
//! from what the frame rendered. A foveated frame's composition happens in it (the fovea over
//! the bilinearly upscaled periphery, smoothstep across the band); for the lens it pre-distorts
//! each eye. Like a VR compositor's pass, it costs one full-view pass however much it does.

use super::model::*;
use super::ops::{Access, AttachmentId};
use super::pipeline::{Constant, PipelineDesc, StepContext};
use super::steps::{OutputSource, OutputStep, Step};
use super::stereo_scene::marks_moving;
use super::{ConfigError, OutputFormat, Resolution};
use crate::foveation::{
    ClipNeighbourhood, HistoryFilter, HistoryFormat, NewSample, PeripheryFilter,
};
use crate::shaders::{
    COMPOSITE_VERT, OUTPUT_FRAG, OUTPUT_FRAG_COUNTING, OUTPUT_TEMPORAL_FRAG,
    OUTPUT_TEMPORAL_FRAG_COUNTING,
};
use crate::view::Eye;

/// The output pass: each eye at `eye` size, from `sources` (in eye order; the periphery, then
/// the fovea views of a two-pass foveated frame) as `source` says.
pub(super) fn output_pass(
    sources: Vec<AttachmentId>,
    source: OutputSource,
    lens: bool,
    temporal: bool,
    eye: Resolution,
    attachments: &mut Vec<AttachmentPlan>,
) -> PassPlan {
    let name = match (source, lens, temporal) {
        (OutputSource::Foveated { .. }, true, true) => {
            "output (periphery accumulated, fovea over it, lens-distorted)"
        }
        (OutputSource::Foveated { .. }, false, true) => {
            "output (periphery accumulated, fovea over it)"
        }
        (OutputSource::Foveated { .. }, true, false) => {
            "output (fovea over periphery, lens-distorted)"
        }
        (OutputSource::Foveated { .. }, false, false) => "output (fovea over periphery)",
        (_, true, _) => "output (lens-distorted)",
        (_, false, _) => "output",
    };
    sampling_pass(
        sources,
        eye,
        attachments,
        name,
        PassKind::Output,
        Step::Output(OutputStep {
            lens,
            source,
            temporal,
            periphery_only: false,
        }),
    )
}

/// The pass that accumulates the periphery at its own texels, or at the history's density
/// (`size`, in `format`), before the output pass composes it
/// ([`HistoryAt::Periphery`](crate::foveation::HistoryAt::Periphery)):
/// the output stage's accumulation with no fovea over it and no lens, sampling `sources` as a
/// temporal output pass does. Its target holds each eye's accumulated periphery, which the
/// output pass samples in place of the periphery's own image.
pub(super) fn periphery_accumulation_pass(
    sources: Vec<AttachmentId>,
    source: OutputSource,
    size: Resolution,
    format: Format,
    attachments: &mut Vec<AttachmentPlan>,
) -> PassPlan {
    attachments.push(AttachmentPlan {
        name: "periphery, accumulated",
        role: AttachmentRole::Color,
        format,
        samples: 1,
        width: size.width,
        height: size.height,
        layers: 2,
        read_after_frame: true,
        sampled: false,
        transient: false,
    });
    let target = attachments.len() - 1;
    full_view_pass(
        sources,
        target,
        attachments,
        "periphery accumulated in a pass of its own",
        PassKind::Accumulate,
        Step::Output(OutputStep {
            lens: false,
            source,
            temporal: true,
            periphery_only: true,
        }),
    )
}

/// A full-view pass per eye (multiview) that samples `sources` — which are then stored for it,
/// An output handed in per frame must be the one two-layer image a stereo swapchain holds.
pub(super) fn check_external_output(plan: &FramePlan) -> Result<(), ConfigError> {
    let outputs = plan.outputs();
    let layered = matches!(outputs[..], [id] if plan.attachments[id].layers == 2);
    if plan.external_output && !layered {
        return Err(ConfigError::new(
            "external_output",
            format!("{:?}", plan.output_layout()),
            "a layered output (one two-layer image): multiview, or any foveated frame",
        ));
    }
    Ok(())
}

/// The frame's output images in `format`, and the MSAA colour that resolves into them (a
/// resolve keeps its source's format). sRGB, the default, is what every builder plans.
pub(super) fn apply_output_format(plan: &mut FramePlan, format: OutputFormat) {
    let format = match format {
        OutputFormat::Srgb8 => Format::Rgba8Srgb,
        OutputFormat::Unorm8 => Format::Rgba8Unorm,
        OutputFormat::Float16 => Format::Rgba16F,
    };
    if format == Format::Rgba8Srgb {
        return;
    }
    let outputs = plan.outputs();
    let mut recoloured = outputs.clone();
    for pass in &plan.passes {
        if pass
            .resolve
            .is_some_and(|r| outputs.contains(&r.attachment))
        {
            recoloured.push(pass.color.attachment);
        }
    }
    for id in recoloured {
        plan.attachments[id].format = format;
    }
}

/// not read after the frame — and writes the frame's image at `eye` size: the output stage,
/// radial density reconstruction.
pub(super) fn sampling_pass(
    sources: Vec<AttachmentId>,
    eye: Resolution,
    attachments: &mut Vec<AttachmentPlan>,
    name: &'static str,
    kind: PassKind,
    step: Step,
) -> PassPlan {
    let target = AttachmentPlan {
        name: "stereo colour",
        role: AttachmentRole::Color,
        format: Format::Rgba8Srgb,
        samples: 1,
        width: eye.width,
        height: eye.height,
        layers: 2,
        read_after_frame: true,
        sampled: false,
        transient: false,
    };
    attachments.push(target);
    full_view_pass(
        sources,
        attachments.len() - 1,
        attachments,
        name,
        kind,
        step,
    )
}

/// A full-view pass per eye (multiview) that samples `sources` — which are then stored for it,
/// not read after the frame — and overwrites both layers of `target`.
pub(super) fn full_view_pass(
    sources: Vec<AttachmentId>,
    target: AttachmentId,
    attachments: &mut [AttachmentPlan],
    name: &'static str,
    kind: PassKind,
    step: Step,
) -> PassPlan {
    for &s in &sources {
        attachments[s].read_after_frame = false;
    }
    PassPlan {
        samples: sources,
        steps: vec![step],
        ..PassPlan::new(
            name,
            kind,
            0b11,
            Submission::Multiview,
            Use::new(target, 0, 2, Access::Overwrite),
        )
    }
}

/// The output stage's full-view draw: the lens, the source and, for a foveated frame, where
/// the fovea views lie, whether the periphery is sharpened and how it is upscaled; with
/// accumulation, how the history is read and clipped, and whether the scene passes mark
/// instances that move (only then are they looked for).
pub(super) fn output_pipeline(
    ctx: &StepContext,
    step: &OutputStep,
    plan: &FramePlan,
) -> PipelineDesc {
    let foveation = plan.foveation.as_ref();
    let catmull_rom = foveation.is_some_and(|f| f.periphery_filter == PeripheryFilter::CatmullRom);
    let temporal = foveation.and_then(|f| f.temporal).filter(|_| step.temporal);
    let history_catmull_rom = temporal.is_some_and(|t| t.filter == HistoryFilter::CatmullRom);
    let cross = temporal.is_some_and(|t| t.neighbourhood == ClipNeighbourhood::Cross);
    let weighted = temporal.is_some_and(|t| t.new_sample == NewSample::Weighted);
    let reach = temporal.is_some_and(|t| t.within_deg.is_some());
    let luma = temporal.is_some_and(|t| t.history_format == HistoryFormat::Luma);
    let (fovea_layer, sharpen) = match step.source {
        OutputSource::Foveated {
            fovea_layer,
            sharpen,
        } => (fovea_layer, sharpen),
        _ => (0, false),
    };
    // Accumulation is its own shader: it declares the history's attachment and images.
    let (plain, counting) = if step.temporal {
        (&OUTPUT_TEMPORAL_FRAG, &OUTPUT_TEMPORAL_FRAG_COUNTING)
    } else {
        (&OUTPUT_FRAG, &OUTPUT_FRAG_COUNTING)
    };
    ctx.pipeline(&COMPOSITE_VERT, plain, counting)
        .flag(Constant::Lens, step.lens)
        .constant(Constant::Source, step.source.code())
        .constant(Constant::FoveaLayer, fovea_layer)
        .flag(Constant::Sharpen, sharpen)
        .flag(Constant::CatmullRom, catmull_rom)
        .flag(Constant::HistoryCatmullRom, history_catmull_rom)
        .flag(Constant::CrossNeighbourhood, cross)
        .flag(Constant::WeightedNewSample, weighted)
        .flag(Constant::PeripheryOnly, step.periphery_only)
        .flag(Constant::Reach, reach)
        .flag(Constant::LumaHistory, luma)
        .flag(Constant::Ring, foveation.is_some_and(|f| f.ring.is_some()))
        .flag(Constant::MarkMoving, step.temporal && marks_moving(plan))
        .constant(
            Constant::HistoryOutcomeBase,
            plan.history_outcome_base().unwrap_or(0),
        )
}

impl FramePlan {
    /// Display pixels per degree at `eye`'s lens axis: across the display's field (the lens
    /// model's) when the output is distorted for the lens, the rendered field otherwise, over
    /// the eye's output width.
    pub fn pixels_per_degree(&self, eye: Eye) -> f64 {
        let field = self
            .lens
            .map_or(self.eyes.fov(eye), |l| l.display[eye.index()]);
        field.pixels_per_degree(self.eye_resolution.width)
    }
}
