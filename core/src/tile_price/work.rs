//! Each pass's work as the price takes it: the fragments and vertices counted on the device that
//! ran the frame, times the instructions the tile GPU's compiler made of the step's shaders,
//! and the pass's bytes by the plan's traffic formula.

use ash::vk;

use crate::gpu::ShaderExecutable;
use crate::plan::{CountedStep, FramePlan};
use crate::render::{FrameStats, StepShaders};

/// One step's work.
#[derive(Clone, Debug, PartialEq)]
pub struct StepWork {
    /// What the step draws.
    pub step: CountedStep,
    /// Fragments it shaded (counted), over every view.
    pub fragments: u64,
    /// Its fragment shader's instructions (the tile GPU's compiler's count).
    pub fragment_instructions: f64,
    /// Vertices it ran (three a counted triangle: no vertex reuse assumed).
    pub vertices: u64,
    /// Its vertex shaders' instructions per vertex: the render pass's and the binning pass's.
    pub vertex_instructions: f64,
}

/// One pass's work.
#[derive(Clone, Debug, PartialEq)]
pub struct PassWork {
    /// The pass's name, as the plan prints it.
    pub name: &'static str,
    /// Its steps'.
    pub steps: Vec<StepWork>,
    /// Bytes it moves to and from memory (the plan's traffic formula: loaded, stored,
    /// sampled).
    pub bytes: u64,
}

impl PassWork {
    /// Every instruction its steps ran.
    pub fn instructions(&self) -> f64 {
        self.steps
            .iter()
            .map(|s| {
                s.fragments as f64 * s.fragment_instructions
                    + s.vertices as f64 * s.vertex_instructions
            })
            .sum()
    }

    /// Instructions its fragment shaders ran.
    pub fn fragment_instructions(&self) -> f64 {
        self.steps
            .iter()
            .map(|s| s.fragments as f64 * s.fragment_instructions)
            .sum()
    }

    /// Fragments its steps shaded.
    pub fn fragments(&self) -> u64 {
        self.steps.iter().map(|s| s.fragments).sum()
    }
}

/// Why a frame's work cannot be assembled.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum WorkError {
    /// A step of the tile GPU's plan that the counting frame did not count.
    #[error("pass {pass}, step {step}: the counting frame counted no such step (its plan differs from the tile GPU's)")]
    Uncounted {
        /// The pass's name.
        pass: &'static str,
        /// The step's name.
        step: &'static str,
    },
    /// A step whose pipeline has no instruction count from the driver.
    #[error("pass {pass}, step {step}: the driver reported no {stage} instruction count")]
    NoStatistics {
        /// The pass's name.
        pass: &'static str,
        /// The step's name.
        step: &'static str,
        /// The stage: fragment or vertex.
        stage: &'static str,
    },
}

/// The driver's instruction count of the executables running `stage` (turnip's "Instruction
/// Count", RADV's "Instructions"), summed: a vertex stage's render and binning executables.
pub(super) fn instructions(
    executables: &[ShaderExecutable],
    stage: vk::ShaderStageFlags,
) -> Option<f64> {
    let counts: Vec<f64> = executables
        .iter()
        .filter(|e| e.stages.contains(stage))
        .map(|e| {
            ["Instruction Count", "Instructions"]
                .iter()
                .find_map(|n| e.statistic(n))
                .map(|v| v.as_f64())
        })
        .collect::<Option<_>>()?;
    (!counts.is_empty()).then(|| counts.iter().sum())
}

/// The work of each pass of `plan` (the tile GPU's plan, whose pipelines `shaders` reports),
/// with the fragments and triangles `counted` (a counting frame of the same scene, views and
/// gaze, on the device that ran it) measured for the steps and passes of the same names.
pub fn frame_work(
    plan: &FramePlan,
    shaders: &[StepShaders],
    counted: &FrameStats,
) -> Result<Vec<PassWork>, WorkError> {
    let traffic = plan.pass_traffic_bytes();
    let mut work: Vec<PassWork> = plan
        .passes
        .iter()
        .zip(traffic)
        .map(|(p, bytes)| PassWork {
            name: p.name,
            steps: Vec::new(),
            bytes,
        })
        .collect();
    for s in shaders {
        let uncounted = || WorkError::Uncounted {
            pass: s.pass,
            step: s.step.name(),
        };
        let missing = |stage| WorkError::NoStatistics {
            pass: s.pass,
            step: s.step.name(),
            stage,
        };
        let nth = work[s.pass_index]
            .steps
            .iter()
            .filter(|w| w.step == s.step)
            .count();
        let fragments = counted
            .steps
            .iter()
            .filter(|c| c.pass == s.pass && c.step == s.step)
            .nth(nth)
            .ok_or_else(uncounted)?
            .total();
        // A pass's triangles are its scene's where it draws one, else its first step's.
        let scene_step = plan.passes[s.pass_index]
            .steps
            .iter()
            .position(|st| st.counted() == CountedStep::Scene)
            .unwrap_or(0);
        let is_drawer = work[s.pass_index].steps.len() == scene_step;
        let triangles = match is_drawer {
            true => counted
                .pass_names
                .iter()
                .position(|&n| n == s.pass)
                .and_then(|i| counted.pass_triangles.get(i).copied())
                .ok_or_else(uncounted)?,
            false => 0,
        };
        let fragment = vk::ShaderStageFlags::FRAGMENT;
        work[s.pass_index].steps.push(StepWork {
            step: s.step,
            fragments,
            fragment_instructions: instructions(s.executables, fragment)
                .ok_or_else(|| missing("fragment"))?,
            vertices: 3 * triangles,
            vertex_instructions: instructions(s.executables, vk::ShaderStageFlags::VERTEX)
                .ok_or_else(|| missing("vertex"))?,
        });
    }
    Ok(work)
}
