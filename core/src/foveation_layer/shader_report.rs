//! What the device's compiler made of each step's pipeline, where the device reports it
//! (`VK_KHR_pipeline_executable_properties`): the figures a tile GPU's cost is priced from.

use crate::gpu::ShaderExecutable;
use crate::plan::{CountedStep, PipelineDesc};

use super::FoveationLayer;

/// One step of the frame, and the executables its pipeline compiled to.
#[derive(Clone, Debug)]
pub struct StepShaders<'a> {
    /// The pass's index in the plan.
    pub pass_index: usize,
    /// The pass's name in the plan.
    pub pass: &'static str,
    /// What the step draws (its name in fragment counts).
    pub step: CountedStep,
    /// The pipeline, as the plan states it (its `Display` names its shaders and state).
    pub pipeline: &'a PipelineDesc,
    /// The pass's samples per pixel.
    pub samples: u32,
    /// The pass's multiview view mask (0: no multiview).
    pub view_mask: u32,
    /// The driver's executables and their statistics; empty for an engine's scene step (drawn
    /// with the engine's own pipelines).
    pub executables: &'a [ShaderExecutable],
}

impl StepShaders<'_> {
    /// The views the step draws (1 for a pass without multiview).
    pub fn views(&self) -> u32 {
        self.view_mask.count_ones().max(1)
    }
}

impl FoveationLayer {
    /// Every step's pipeline as the driver's compiler reported it, in the plan's order; `None`
    /// where the device does not report statistics (no `VK_KHR_pipeline_executable_properties`,
    /// every lavapipe among them, or an engine's device).
    pub fn shader_statistics(&self) -> Option<Vec<StepShaders<'_>>> {
        self.gpu.executable_properties.as_ref()?;
        let mut steps = Vec::new();
        for (pass_index, (pass, bound)) in self.plan.passes.iter().zip(&self.steps).enumerate() {
            let samples = self.plan.attachments[pass.color.attachment].samples;
            for ((step, pipeline), bound) in pass.steps.iter().zip(&pass.pipelines).zip(bound) {
                let executables = bound
                    .pipeline
                    .as_ref()
                    .and_then(|p| p.statistics.as_deref())
                    .unwrap_or(&[]);
                steps.push(StepShaders {
                    pass_index,
                    pass: pass.name,
                    step: step.counted(),
                    pipeline,
                    samples,
                    view_mask: pass.view_mask,
                    executables,
                });
            }
        }
        Some(steps)
    }
}
