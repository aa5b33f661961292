//! The stereo scene pass(es): their attachments and their scene step, as the submission strategy
//! says (masks, MFFR's far composite and the probe are their own builders' steps).

use super::derive::Access;
use super::model::*;
use super::steps::Step;
use super::{RenderConfig, Resolution, StereoMode};
use crate::cull::Strategy;
use crate::view::Eye;

/// The scene pass(es) of a stereo frame and the attachments they use.
pub(super) fn scene_passes(
    config: &RenderConfig,
    eye: Resolution,
    layout: TargetLayout,
    far_field: Option<AttachmentId>,
    attachments: &mut Vec<AttachmentPlan>,
) -> Vec<PassPlan> {
    let msaa = config.msaa > 1;
    // Image shape: one layer per view for multiview, one double-wide image for the side-by-side
    // modes; two-pass renders one eye per pass into single-layer scratch images and resolves
    // into its eye's layer of the output (layered) or its eye's own image (per eye).
    let two_pass = config.stereo == StereoMode::TwoPass;
    let (width, layers) = match layout {
        TargetLayout::Layered if two_pass => (eye.width, 1),
        TargetLayout::Layered => (eye.width, config.views),
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
        _ => vec![add(
            if config.views == 4 {
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

    let pass = |name, view_mask, output: AttachmentId, submission| {
        let whole = |id, access| Use::new(id, 0, layers, access);
        // A single-eye pass into a layered output writes only its eye's layer.
        let output_use = |access| match submission {
            Submission::SingleEye(eye) if output_layers == 2 => {
                Use::new(output, eye.index() as u32, 1, access)
            }
            _ => whole(output, access),
        };
        PassPlan {
            name,
            view_mask,
            color: color.map_or(output_use(Access::Clear), |c| whole(c, Access::Clear)),
            depth: Some(whole(depth, Access::Clear)),
            resolve: color.map(|_| output_use(Access::Overwrite)),
            submission,
            kind: PassKind::Scene,
            samples: far_field.into_iter().collect(),
            // The scene step; other techniques' builders add theirs around it.
            steps: vec![Step::Scene {
                draw_set: match (far_field, config.culling, submission) {
                    (Some(_), _, _) => DrawSet::NearField,
                    (None, None, _) => DrawSet::All,
                    (None, Some(c), Submission::SingleEye(eye))
                        if c.strategy == Strategy::PerEye =>
                    {
                        DrawSet::VisibleToEye(eye)
                    }
                    (None, Some(_), _) => DrawSet::Visible,
                },
                cull_slot: None,
                stencil: None,
            }],
            depth_clamp: false,
            guard_band: 1,
        }
    };
    match config.stereo {
        StereoMode::Multiview => {
            let (name, mask) = if config.views == 4 {
                ("scene (foveated multiview)", 0b1111)
            } else {
                ("scene (multiview)", 0b11)
            };
            vec![pass(name, mask, outputs[0], Submission::Multiview)]
        }
        StereoMode::TwoPass => vec![
            pass(
                "scene (left eye)",
                0,
                outputs[0],
                Submission::SingleEye(Eye::Left),
            ),
            pass(
                "scene (right eye)",
                0,
                outputs[outputs.len() - 1],
                Submission::SingleEye(Eye::Right),
            ),
        ],
        StereoMode::PerObject => vec![pass(
            "scene (per-object)",
            0,
            outputs[0],
            Submission::PerObject,
        )],
        StereoMode::Instanced => vec![pass(
            "scene (instanced)",
            0,
            outputs[0],
            Submission::Instanced,
        )],
    }
}
