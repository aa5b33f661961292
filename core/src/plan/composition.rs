//! Foveated composition: each eye at full resolution from the four views the scene pass
//! rendered.

use super::derive::Access;
use super::model::*;
use super::steps::Step;
use super::Resolution;

/// Composition of a foveated frame: each eye at full resolution, the fovea over the bilinearly
/// upscaled periphery, from the scene pass's views sampled as a texture (which therefore is
/// stored, not read after the frame).
pub(super) fn composite_pass(
    scene: &PassPlan,
    eye: Resolution,
    attachments: &mut Vec<AttachmentPlan>,
) -> PassPlan {
    output_pass(
        scene,
        eye,
        attachments,
        "composite (fovea over periphery)",
        PassKind::Composite,
        Step::Composite,
    )
}

/// A full-view pass per eye (multiview) that samples the scene pass's output — which is then
/// stored for it, not read after the frame — and writes the frame's output at `eye` size:
/// foveated composition, radial density reconstruction.
pub(super) fn output_pass(
    scene: &PassPlan,
    eye: Resolution,
    attachments: &mut Vec<AttachmentPlan>,
    name: &'static str,
    kind: PassKind,
    step: Step,
) -> PassPlan {
    let views = scene
        .resolve
        .map_or(scene.color.attachment, |r| r.attachment);
    attachments[views].read_after_frame = false;
    attachments.push(AttachmentPlan {
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
    });
    PassPlan {
        name,
        kind,
        view_mask: 0b11,
        color: Use::new(attachments.len() - 1, 0, 2, Access::Overwrite),
        depth: None,
        resolve: None,
        samples: vec![views],
        submission: Submission::Multiview,
        steps: vec![step],
        depth_clamp: false,
        guard_band: 1,
    }
}
