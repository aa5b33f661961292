//! The images an engine's draws go into, when the engine makes them itself: what each must be
//! ([`view_images`]: every attachment of the passes it draws into, as the plan describes it),
//! and the check of what it hands in ([`HandedImage`]) — each refusal names the image, the
//! field, the value and what the plan needs.

use ash::vk;

use super::targets::image_desc;
use crate::gpu::ImageDesc;
use crate::plan::{AttachmentId, ConfigError, FramePlan, PassKind};

/// An image an engine's draws go into, as the plan needs it.
#[derive(Clone, Debug)]
pub struct ViewImage {
    /// The attachment it stands for (an index into [`FramePlan::attachments`]).
    pub attachment: AttachmentId,
    /// Its attachment's name in the plan.
    pub name: &'static str,
    /// How to make it: format, size, layers, samples, usage (at least these flags).
    pub desc: ImageDesc<'static>,
}

/// An image of the engine's handed in for one of [`view_images`], described as the engine
/// made it.
#[derive(Clone, Copy, Debug)]
pub struct HandedImage<'a> {
    /// The attachment it stands for ([`ViewImage::attachment`]).
    pub attachment: AttachmentId,
    /// The image, of the layer's device, alive as long as the layer.
    pub image: vk::Image,
    /// How it was made.
    pub desc: ImageDesc<'a>,
}

/// Every image the passes an engine draws into use — colour, depth, their resolves; both
/// images of the periphery's depth when it is kept for the next frame — as the plan needs
/// them made. An engine that makes its own hands all of them, or none.
pub fn view_images(plan: &FramePlan) -> Vec<ViewImage> {
    let mut ids: Vec<AttachmentId> = (plan.passes.iter())
        .filter(|p| p.kind == PassKind::Scene)
        .flat_map(|p| p.uses().map(|u| u.attachment))
        .collect();
    // The pair's other image: odd frames draw into it.
    for pair in plan.history_pairs() {
        if ids.contains(&pair.read) || ids.contains(&pair.written) {
            ids.extend([pair.read, pair.written]);
        }
    }
    ids.sort();
    ids.dedup();
    ids.into_iter()
        .map(|id| ViewImage {
            attachment: id,
            name: plan.attachments[id].name,
            desc: image_desc(plan, id),
        })
        .collect()
}

/// `handed` checked against what `plan` needs: each a view image, made as it says, none
/// twice, and all of them (or none); the images by attachment.
pub(super) fn check_handed(
    plan: &FramePlan,
    handed: &[HandedImage],
) -> Result<Vec<(AttachmentId, vk::Image)>, ConfigError> {
    if handed.is_empty() {
        return Ok(Vec::new());
    }
    let needed = view_images(plan);
    let mut images = Vec::with_capacity(handed.len());
    for h in handed {
        let Some(want) = needed.iter().find(|v| v.attachment == h.attachment) else {
            let names: Vec<String> = (needed.iter())
                .map(|v| format!("{} ({})", v.attachment, v.name))
                .collect();
            return Err(ConfigError::new(
                "view image attachment",
                h.attachment,
                format!("one the engine's passes draw into: {}", names.join(", ")),
            ));
        };
        if images.iter().any(|&(id, _)| id == h.attachment) {
            return Err(ConfigError::new(
                "view image attachment",
                format!("{} ({}) twice", h.attachment, want.name),
                "each image once",
            ));
        }
        check_desc(want, &h.desc)?;
        images.push((h.attachment, h.image));
    }
    if let Some(missing) = needed
        .iter()
        .find(|v| images.iter().all(|i| i.0 != v.attachment))
    {
        return Err(ConfigError::new(
            "view images",
            format!("none for {} ('{}')", missing.attachment, missing.name),
            "every image the engine's passes draw into (view_images), or none for foveate's own",
        ));
    }
    Ok(images)
}

/// `got` made as `want` needs: its format, size, layers and samples, and at least its usage.
fn check_desc(want: &ViewImage, got: &ImageDesc) -> Result<(), ConfigError> {
    let need = &want.desc;
    let differ = |field: &'static str, got: String, need: String| {
        let value = format!("{got} for '{}'", want.name);
        Err(ConfigError::new(field, value, need))
    };
    if got.format != need.format {
        return differ(
            "view image format",
            format!("{:?}", got.format),
            format!("{:?}", need.format),
        );
    }
    if (got.width, got.height) != (need.width, need.height) {
        let size = |d: &ImageDesc| format!("{}x{}", d.width, d.height);
        return differ("view image extent", size(got), size(need));
    }
    if got.samples != need.samples {
        return differ(
            "view image samples",
            got.samples.to_string(),
            need.samples.to_string(),
        );
    }
    if got.layers != need.layers {
        return differ(
            "view image layers",
            got.layers.to_string(),
            need.layers.to_string(),
        );
    }
    if !got.usage.contains(need.usage) {
        let need = format!("at least {:?}", need.usage);
        return differ("view image usage", format!("{:?}", got.usage), need);
    }
    Ok(())
}
