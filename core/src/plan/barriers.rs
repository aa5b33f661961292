//! Barriers, derived from who touches an image and who touches it next: a pass waits for the
//! previous touch of each image it uses and makes its own touches safe for the next one. The
//! frame repeats, so the first touch of a frame follows the last of the frame before (or the
//! readback of its output). A render pass executes them as its external subpass dependencies —
//! on a tile GPU a pass then waits only for what it reads, not for every earlier pass.

use super::model::{FramePlan, PassPlan};
use super::ops::{AttachmentId, Barrier, PassBarriers, Touch};

/// One touch in frame order: by pass `pass` (`None`: after the frame), of some layers.
#[derive(Clone, Copy)]
struct Touched {
    pass: Option<usize>,
    touch: Touch,
    layers: (u32, u32),
}

impl Touched {
    fn overlaps(&self, other: &Touched) -> bool {
        let (a, b) = (self.layers, other.layers);
        a.0 < b.0 + b.1 && b.0 < a.0 + a.1
    }
}

/// Every touch of `attachment` in frame order: each pass's attachment uses and samples, then
/// the frame's reader. The two images of a history pair are touched as one: they swap roles
/// every frame, so what one is sampled after is the other's write in the frame before.
fn touches(plan: &FramePlan, attachment: AttachmentId) -> Vec<Touched> {
    let all_layers = (0, plan.attachments[attachment].layers);
    let same = |id: AttachmentId| match plan.history_pairs().find(|h| h.contains(id)) {
        Some(h) => vec![h.read, h.written],
        None => vec![id],
    };
    let mut touched = Vec::new();
    for (index, pass) in plan.passes.iter().enumerate() {
        for id in same(attachment) {
            let pass_touches = pass_touches(pass, id, all_layers);
            touched.extend(pass_touches.map(|(touch, layers)| Touched {
                pass: Some(index),
                touch,
                layers,
            }));
        }
    }
    if plan.attachments[attachment].read_after_frame {
        touched.push(Touched {
            pass: None,
            touch: Touch::ReadAfterFrame,
            layers: all_layers,
        });
    }
    touched
}

fn pass_touches(
    pass: &PassPlan,
    attachment: AttachmentId,
    all_layers: (u32, u32),
) -> impl Iterator<Item = (Touch, (u32, u32))> + '_ {
    let sampled = pass
        .samples
        .contains(&attachment)
        .then_some((Touch::Sampled, all_layers));
    let depth = pass.depth.iter().map(|u| (Touch::DepthAttachment, u));
    // Resolves, depth's included, happen at colour attachment output with colour writes.
    let colour = [
        Some(&pass.color),
        pass.resolve.as_ref(),
        pass.history.as_ref(),
        pass.depth_resolve.as_ref(),
    ]
    .into_iter()
    .flatten()
    .map(|u| (Touch::ColourAttachment, u));
    sampled.into_iter().chain(
        colour
            .chain(depth)
            .filter(move |(_, u)| u.attachment == attachment)
            .map(|(touch, u)| (touch, (u.base_layer, u.layer_count))),
    )
}

/// Each pass's barriers. A touch of an image waits on the nearest earlier touch of the same
/// layers (going round to the previous frame's, which for an image one pass alone touches is
/// its own) and signals the nearest later one (going round to the next frame); reads after
/// reads need none.
pub(super) fn derive_barriers(plan: &FramePlan) -> Vec<PassBarriers> {
    let mut barriers = vec![PassBarriers::default(); plan.passes.len()];
    for attachment in 0..plan.attachments.len() {
        let touched = touches(plan, attachment);
        let n = touched.len();
        for (i, t) in touched.iter().enumerate() {
            let Some(pass) = t.pass else { continue };
            // Earlier touches, nearest first, round to the previous frame's (this very touch
            // last); later ones likewise.
            let earlier = (1..=n).map(|k| &touched[(i + n - k) % n]);
            let later = (1..=n).map(|k| &touched[(i + k) % n]);
            let other = |o: &&Touched| o.overlaps(t);
            let needed = |a: Touch, b: Touch| a.writes() || b.writes();
            if let Some(before) = earlier.clone().find(other) {
                if needed(before.touch, t.touch) {
                    barriers[pass].wait.push(Barrier {
                        attachment,
                        from: before.touch,
                        to: t.touch,
                    });
                }
            }
            if let Some(after) = later.clone().find(other) {
                if needed(t.touch, after.touch) {
                    barriers[pass].signal.push(Barrier {
                        attachment,
                        from: t.touch,
                        to: after.touch,
                    });
                }
            }
        }
    }
    for b in &mut barriers {
        b.wait.sort();
        b.wait.dedup();
        b.signal.sort();
        b.signal.dedup();
    }
    barriers
}
