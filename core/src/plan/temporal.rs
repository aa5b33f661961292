//! Temporal accumulation of the periphery (maths: `foveation/temporal.rs`; executor: the
//! output stage's, `foveation_layer/output.rs` with `foveation_layer/temporal.rs`; shader: `output.frag`'s
//! `accumulate`). It is folded into the output stage, the one full-view pass a frame has
//! anyway: that pass reads the jittered periphery, its depth and the history, and writes the
//! next history as a second attachment beside what the display shows. The history is a pair of
//! images that swap roles every frame (a pass cannot sample the image it writes), so nothing
//! copies it; at the output's pixels, in 32 bits a pixel (10-bit square roots of linear light).
//! With [`HistoryAt::Periphery`](crate::foveation::HistoryAt::Periphery) the same accumulation
//! runs in a pass of its own at the periphery's size (`output::periphery_accumulation_pass`),
//! its history at the periphery's texels, and the output pass composes its image.

use crate::foveation::HistoryFormat;

use super::model::{AttachmentPlan, AttachmentRole, Format, HistoryPair, PassKind, PassPlan};
use super::ops::{Access, AttachmentId};
use super::Resolution;
use super::Use;

/// What temporal accumulation adds to a frame whose scene passes are planned.
pub(super) struct Accumulation {
    /// The history pair; the output pass samples `read` and writes `written` (even frames).
    pub pair: HistoryPair,
    /// The periphery pass's depth as a pair: the pass writes `written` (even frames), the
    /// output pass samples it to reproject and `read`, the frame before's, to test the
    /// history's surface.
    pub depth: HistoryPair,
}

impl Accumulation {
    /// The images the output pass samples for it, after its own sources (the executor's
    /// binding order: history, this frame's depth, the frame before's).
    pub fn samples(&self) -> [AttachmentId; 3] {
        [self.pair.read, self.depth.written, self.depth.read]
    }

    /// The output pass's second colour attachment: the next history, overwritten whole.
    pub fn written(&self) -> super::Use {
        super::Use::new(self.pair.written, 0, 2, Access::Overwrite)
    }
}

/// Adds the history pair at `eye` size (`history_size`'s), in the format `temporal` keeps;
/// `None` without a periphery pass with depth. A multisampled periphery resolves its depth to one sample in its pass (sample 0:
/// the depth at the pixel's centre, as a single-sample periphery has it), and the pair holds
/// that instead; the multisampled depth stays on tile.
pub(super) fn add_accumulation(
    passes: &mut [PassPlan],
    attachments: &mut Vec<AttachmentPlan>,
    eye: Resolution,
    temporal: crate::foveation::TemporalConfig,
) -> Option<Accumulation> {
    let periphery = passes
        .iter_mut()
        .find(|p| p.kind == PassKind::Scene && p.first_view == 0)?;
    let depth_use = periphery.depth?;
    let mut depth = depth_use.attachment;
    if attachments[depth].samples > 1 {
        attachments.push(AttachmentPlan {
            name: "periphery depth, resolved (even frames write)",
            format: Format::D32,
            samples: 1,
            ..attachments[depth].clone()
        });
        depth = attachments.len() - 1;
        periphery.depth_resolve = Some(Use::new(
            depth,
            depth_use.base_layer,
            depth_use.layer_count,
            Access::Overwrite,
        ));
    }
    let previous_depth = AttachmentPlan {
        name: "periphery depth (even frames read)",
        ..attachments[depth].clone()
    };
    attachments.push(previous_depth);
    let previous_depth = attachments.len() - 1;
    let image = |name| AttachmentPlan {
        name,
        role: AttachmentRole::Color,
        format: match temporal.history_format {
            HistoryFormat::Colour => Format::Rgb10A2,
            HistoryFormat::Luma => Format::R8,
        },
        samples: 1,
        width: eye.width,
        height: eye.height,
        layers: 2,
        read_after_frame: false,
        sampled: false,
        transient: false,
    };
    attachments.push(image("periphery history (even frames read)"));
    attachments.push(image("periphery history (even frames write)"));
    let n = attachments.len();
    Some(Accumulation {
        pair: HistoryPair {
            read: n - 2,
            written: n - 1,
        },
        depth: HistoryPair {
            read: previous_depth,
            written: depth,
        },
    })
}

/// The history's size: the output's (`eye`); in a pass of its own, the periphery's (`periphery`,
/// its size) or the screen's at the history's own density
/// ([`TemporalConfig::history_density`](crate::foveation::TemporalConfig::history_density)),
/// rounded as the periphery's views are.
pub(super) fn history_size(
    temporal: Option<crate::foveation::TemporalConfig>,
    periphery: Option<Resolution>,
    eye: Resolution,
) -> Resolution {
    let Some(periphery) = periphery else {
        return eye;
    };
    let Some(density) = temporal.and_then(|t| t.history_density) else {
        return periphery;
    };
    eye.scaled(density)
}

/// The periphery's image (its resolve when multisampled), its size and format: what the
/// periphery pass (the scene pass of views 0 and 1) leaves for the passes after it.
pub(super) fn periphery_image(
    passes: &[PassPlan],
    attachments: &[AttachmentPlan],
) -> Option<(AttachmentId, Resolution, Format)> {
    let pass = passes
        .iter()
        .find(|p| p.kind == PassKind::Scene && p.first_view == 0)?;
    let id = pass.resolve.unwrap_or(pass.color).attachment;
    let a = &attachments[id];
    let size = Resolution {
        width: a.width,
        height: a.height,
    };
    Some((id, size, a.format))
}
