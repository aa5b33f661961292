//! The stereo scene pass(es): their attachments and their scene step, as the submission strategy
//! and a foveated frame's layout say (masks, MFFR's far composite and the probe are their own
//! builders' steps).

use super::model::*;
use super::ops::{Access, AttachmentId};
use super::pipeline::{Constant, PipelineDesc, StepContext, VertexInput};
use super::steps::{DrawSet, Step};
use super::{FoveaLayout, RenderConfig, Resolution, StereoMode};
use crate::cull::Strategy;
use crate::shaders::{
    SCENE_FRAG, SCENE_FRAG_COUNTING, SCENE_LIT_FRAG, SCENE_LIT_FRAG_COUNTING, SCENE_MASKED_FRAG,
    SCENE_MASKED_FRAG_COUNTING, SCENE_VERT, SCENE_VERT_INDIRECT,
};
use crate::view::Eye;

/// A foveated frame's views as planned: the resolved layout, whether the fovea views draw
/// only what their frusta see, and each view pair's size and samples.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) struct FoveaPasses {
    pub layout: FoveaLayout,
    pub cull: bool,
    pub periphery: ViewSet,
    pub fovea: ViewSet,
    /// A parafoveal ring: the fovea's pass renders its two views too, as layers 2, 3 of the
    /// fovea's images.
    pub ring: bool,
}

/// The size and sample count of a pair of views.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) struct ViewSet {
    pub resolution: Resolution,
    pub samples: u32,
}

/// The images the scene passes render into.
struct SceneTargets {
    /// The MSAA colour image, when multisampled (the outputs are then its resolve targets).
    color: Option<AttachmentId>,
    depth: AttachmentId,
    /// Where the views end up: one image, or one per eye (per-eye layout) or per view pair
    /// (the two-pass fovea layout).
    outputs: Vec<AttachmentId>,
    /// Layers of the scratch images, and of the outputs.
    layers: u32,
    output_layers: u32,
}

/// Adds the scene passes' images to `attachments`.
fn scene_targets(
    config: &RenderConfig,
    eye: Resolution,
    layout: TargetLayout,
    fovea: Option<FoveaPasses>,
    attachments: &mut Vec<AttachmentPlan>,
) -> SceneTargets {
    let two_pass_fovea = fovea.is_some_and(|f| f.layout == FoveaLayout::TwoPass);
    let msaa = config.msaa > 1;
    // Image shape: one layer per view for multiview, one double-wide image for the side-by-side
    // modes; two-pass renders one eye per pass into single-layer scratch images and resolves
    // into its eye's layer of the output (layered) or its eye's own image (per eye).
    let two_pass = config.stereo == StereoMode::TwoPass;
    let (width, layers) = match layout {
        TargetLayout::Layered if two_pass => (eye.width, 1),
        TargetLayout::Layered if two_pass_fovea => (eye.width, 2),
        TargetLayout::Layered => (eye.width, config.view_count()),
        TargetLayout::SideBySide => (eye.width * 2, 1),
        TargetLayout::PerEye => (eye.width, 1),
    };
    let output_layers = if two_pass && layout == TargetLayout::Layered {
        2
    } else {
        layers
    };
    let mut add = |name, role, format, samples, read_after_frame, layers| {
        attachments.push(AttachmentPlan {
            name,
            role,
            format,
            samples,
            width,
            height: eye.height,
            layers,
            read_after_frame,
            sampled: false,
            transient: false,
        });
        attachments.len() - 1
    };
    // Scratch images are shared by the passes (two-pass reuses them for the second eye).
    let color = msaa.then(|| {
        add(
            "scene colour (MSAA)",
            AttachmentRole::Color,
            Format::Rgba8Srgb,
            config.msaa,
            false,
            layers,
        )
    });
    // D32 until a step that tests stencil asks for D32S8 (`derive`).
    let depth = add(
        "scene depth",
        AttachmentRole::Depth,
        Format::D32,
        config.msaa,
        false,
        layers,
    );
    let output_role = if msaa {
        AttachmentRole::Resolve
    } else {
        AttachmentRole::Color
    };
    let outputs: Vec<AttachmentId> = match layout {
        TargetLayout::PerEye => vec![
            add(
                "left eye colour",
                output_role,
                Format::Rgba8Srgb,
                1,
                true,
                1,
            ),
            add(
                "right eye colour",
                output_role,
                Format::Rgba8Srgb,
                1,
                true,
                1,
            ),
        ],
        _ if two_pass_fovea => vec![
            add(
                "periphery views",
                output_role,
                Format::Rgba8Srgb,
                1,
                true,
                2,
            ),
            add("fovea views", output_role, Format::Rgba8Srgb, 1, true, 2),
        ],
        _ => vec![add(
            if config.view_count() == 4 {
                "views (periphery, fovea)"
            } else {
                "stereo colour"
            },
            output_role,
            Format::Rgba8Srgb,
            1,
            true,
            output_layers,
        )],
    };
    SceneTargets {
        color,
        depth,
        outputs,
        layers,
        output_layers,
    }
}

/// The two-pass fovea layout's images when the periphery and the fovea differ in size or
/// samples: each pair of views its own scratch images and its own 2-layer output.
fn split_targets(fovea: FoveaPasses, attachments: &mut Vec<AttachmentPlan>) -> [SceneTargets; 2] {
    let mut targets = |set: ViewSet, names: [&'static str; 3], layers: u32| {
        let mut add = |name, role, format, samples, read_after_frame| {
            attachments.push(AttachmentPlan {
                name,
                role,
                format,
                samples,
                width: set.resolution.width,
                height: set.resolution.height,
                layers,
                read_after_frame,
                sampled: false,
                transient: false,
            });
            attachments.len() - 1
        };
        let msaa = set.samples > 1;
        let color = msaa.then(|| {
            add(
                names[0],
                AttachmentRole::Color,
                Format::Rgba8Srgb,
                set.samples,
                false,
            )
        });
        let depth = add(
            names[1],
            AttachmentRole::Depth,
            Format::D32,
            set.samples,
            false,
        );
        let role = if msaa {
            AttachmentRole::Resolve
        } else {
            AttachmentRole::Color
        };
        let output = add(names[2], role, Format::Rgba8Srgb, 1, true);
        SceneTargets {
            color,
            depth,
            outputs: vec![output],
            layers,
            output_layers: layers,
        }
    };
    [
        targets(
            fovea.periphery,
            [
                "periphery colour (MSAA)",
                "periphery depth",
                "periphery views",
            ],
            2,
        ),
        targets(
            fovea.fovea,
            ["fovea colour (MSAA)", "fovea depth", "fovea views"],
            if fovea.ring { 4 } else { 2 },
        ),
    ]
}

/// What one scene pass submits and draws.
struct SceneStep {
    submission: Submission,
    draw_set: DrawSet,
}

/// A scene pass into `output` (through the MSAA image, when multisampled) with its scene step;
/// other techniques' builders add theirs around it.
fn scene_pass(
    targets: &SceneTargets,
    name: &'static str,
    view_mask: u32,
    output: AttachmentId,
    scene: SceneStep,
    far_field: Option<AttachmentId>,
) -> PassPlan {
    let whole = |id, access| Use::new(id, 0, targets.layers, access);
    // A single-eye pass into a layered output writes only its eye's layer.
    let output_use = |access| match scene.submission {
        Submission::SingleEye(eye) if targets.output_layers == 2 => {
            Use::new(output, eye.index() as u32, 1, access)
        }
        _ => whole(output, access),
    };
    let color = targets.color;
    PassPlan {
        depth: Some(whole(targets.depth, Access::Clear)),
        resolve: color.map(|_| output_use(Access::Overwrite)),
        samples: far_field.into_iter().collect(),
        steps: vec![Step::scene(scene.draw_set)],
        ..PassPlan::new(
            name,
            PassKind::Scene,
            view_mask,
            scene.submission,
            color.map_or(output_use(Access::Clear), |c| whole(c, Access::Clear)),
        )
    }
}

/// What the eye (periphery) views of a scene pass submitted as `submission` draw.
fn eye_draw_set(mffr: bool, config: &RenderConfig, submission: Submission) -> DrawSet {
    match (mffr, config.culling, submission) {
        (true, _, _) => DrawSet::NearField,
        (false, None, _) => DrawSet::All,
        (false, Some(c), Submission::SingleEye(eye)) if c.strategy == Strategy::PerEye => {
            DrawSet::VisibleToEye(eye)
        }
        (false, Some(_), _) => DrawSet::Visible,
    }
}

/// The scene pass(es) of a stereo frame and the attachments they use.
pub(super) fn scene_passes(
    config: &RenderConfig,
    eye: Resolution,
    layout: TargetLayout,
    far_field: Option<AttachmentId>,
    fovea: Option<FoveaPasses>,
    attachments: &mut Vec<AttachmentPlan>,
) -> Vec<PassPlan> {
    // Each pass's targets and output: one set shared by every pass, or, for a two-pass
    // foveated frame whose view pairs differ, one set per pair.
    let split =
        fovea.filter(|f| f.layout == FoveaLayout::TwoPass && (f.periphery != f.fovea || f.ring));
    let (targets, pair_targets) = match split {
        Some(f) => {
            let [periphery, fovea] = split_targets(f, attachments);
            let outputs = vec![periphery.outputs[0], fovea.outputs[0]];
            (periphery, Some((fovea, outputs)))
        }
        None => (scene_targets(config, eye, layout, fovea, attachments), None),
    };
    let outputs = pair_targets
        .as_ref()
        .map_or(&targets.outputs, |(_, outputs)| outputs);
    let fovea_targets = pair_targets.as_ref().map_or(&targets, |(t, _)| t);
    let eye_set = |submission| eye_draw_set(far_field.is_some(), config, submission);

    let pass = |name, view_mask, output, submission, draw_set| {
        let scene = SceneStep {
            submission,
            draw_set,
        };
        scene_pass(&targets, name, view_mask, output, scene, far_field)
    };
    let multiview = Submission::Multiview;
    // The fovea views' own set, when culled (not with MFFR: they draw its near field).
    let fovea_culled = fovea.is_some_and(|f| f.cull) && far_field.is_none();
    match (config.stereo, fovea) {
        (StereoMode::Multiview, Some(f)) if f.layout == FoveaLayout::TwoPass => {
            let periphery = pass(
                "scene (periphery views)",
                0b11,
                outputs[0],
                multiview,
                eye_set(multiview),
            );
            let fovea_set = if fovea_culled {
                DrawSet::Fovea
            } else {
                eye_set(multiview)
            };
            let scene = SceneStep {
                submission: multiview,
                draw_set: fovea_set,
            };
            let (name, view_mask) = if f.ring {
                ("scene (fovea and ring views)", 0b1111)
            } else {
                ("scene (fovea views)", 0b11)
            };
            let fovea = PassPlan {
                first_view: 2,
                ..scene_pass(fovea_targets, name, view_mask, outputs[1], scene, far_field)
            };
            vec![periphery, fovea]
        }
        (StereoMode::Multiview, Some(_)) => {
            let set = if fovea_culled {
                DrawSet::FoveaTagged
            } else {
                eye_set(multiview)
            };
            vec![pass(
                "scene (foveated multiview)",
                0b1111,
                outputs[0],
                multiview,
                set,
            )]
        }
        (StereoMode::Multiview, None) => vec![pass(
            "scene (multiview)",
            0b11,
            outputs[0],
            multiview,
            eye_set(multiview),
        )],
        (StereoMode::TwoPass, _) => Eye::BOTH
            .into_iter()
            .map(|eye| {
                let submission = Submission::SingleEye(eye);
                let name = match eye {
                    Eye::Left => "scene (left eye)",
                    Eye::Right => "scene (right eye)",
                };
                let output = outputs[eye.index().min(outputs.len() - 1)];
                pass(name, 0, output, submission, eye_set(submission))
            })
            .collect(),
        (StereoMode::PerObject, _) => vec![pass(
            "scene (per-object)",
            0,
            outputs[0],
            Submission::PerObject,
            eye_set(Submission::PerObject),
        )],
        (StereoMode::Instanced, _) => vec![pass(
            "scene (instanced)",
            0,
            outputs[0],
            Submission::Instanced,
            eye_set(Submission::Instanced),
        )],
    }
}

/// The scene's meshes: depth tested and written, back faces culled; the vertex shader reads
/// the instance ids chosen per frame when the step has a cull slot (`ids`), the fragment
/// shader shades as the scene's materials ask (flat, lit, lit with alpha masks).
pub(super) fn scene_pipeline(
    ctx: &StepContext,
    plan: &FramePlan,
    pass: &PassPlan,
    draw_set: DrawSet,
    ids: bool,
) -> PipelineDesc {
    let vertex = if ids {
        &SCENE_VERT_INDIRECT
    } else {
        &SCENE_VERT
    };
    let desc = if plan.alpha_mask {
        ctx.pipeline(vertex, &SCENE_MASKED_FRAG, &SCENE_MASKED_FRAG_COUNTING)
    } else if plan.lit {
        ctx.pipeline(vertex, &SCENE_LIT_FRAG, &SCENE_LIT_FRAG_COUNTING)
    } else {
        ctx.pipeline(vertex, &SCENE_FRAG, &SCENE_FRAG_COUNTING)
    };
    PipelineDesc {
        vertex_input: VertexInput::SceneVertices,
        cull_back_faces: true,
        depth_test: true,
        depth_clamp: pass.depth_clamp,
        ..desc
    }
    .constant(Constant::ViewSource, view_source(pass.submission))
    .flag(Constant::FoveaTags, draw_set == DrawSet::FoveaTagged)
    .flag(Constant::DepthInAlpha, pass.kind == PassKind::FarField)
    .flag(Constant::MarkMoving, marks_moving(plan))
    .flag(Constant::PeripheryPrefilter, plan.lit && prefilters(plan))
    .constant(Constant::PointLights, plan.point_lights)
}

/// Whether the scene passes mark the pixels of instances that move (alpha 0): only where the
/// periphery's accumulation clips by them (`HistoryClip::Moved`) and instances can move —
/// foveate's moving instances, or an engine's draws, whose moving surfaces it marks itself. The
/// output stage looks for them by the same constant.
pub(super) fn marks_moving(plan: &FramePlan) -> bool {
    let temporal = plan.foveation.and_then(|g| g.temporal);
    (plan.moving_instances().is_some() || plan.engine_draws)
        && temporal.is_some_and(|t| t.clip == crate::foveation::HistoryClip::Moved)
}

/// Whether the lit scene's periphery views prefilter their highlights
/// ([`FoveationConfig::periphery_prefilter`](crate::foveation::FoveationConfig::periphery_prefilter)).
fn prefilters(plan: &FramePlan) -> bool {
    plan.foveation.is_some_and(|g| g.periphery_prefilter)
}

/// The vertex shader's `VIEW_SOURCE` for a submission (see `shaders/scene.vert`).
pub(super) fn view_source(submission: Submission) -> u32 {
    match submission {
        Submission::Multiview => 0,
        Submission::SingleEye(_) | Submission::PerObject | Submission::FarView => 1,
        Submission::Instanced => 2,
    }
}
