//! The derivation rules: from what passes declare about an attachment (its [`Access`]) and
//! who reads it afterwards, to Vulkan load/store ops and transient usage.

use super::model::{Format, FramePlan, PassKind, Use, SKY};
use super::ops::{is_transient, Access, AttachmentId, ClearValue, Layout, LoadOp, StoreOp};
use super::steps::assign_stencil_states;

/// Fills in every use's store op and every attachment's transient flag from declared intent:
/// a use stores only if a later pass keeps its contents, the frame's reader or the next frame
/// needs them, and no later pass replaces them first.
pub(super) fn derive_ops(plan: &mut FramePlan) {
    let all_uses: Vec<(usize, Use)> = plan
        .passes
        .iter()
        .enumerate()
        .flat_map(|(i, p)| p.uses().map(move |u| (i, *u)))
        .collect();
    // Attachments sampled by some pass after pass i.
    let sampled_after: Vec<Vec<AttachmentId>> = (0..plan.passes.len())
        .map(|i| {
            plan.passes[i + 1..]
                .iter()
                .flat_map(|p| p.samples.iter().copied())
                .collect()
        })
        .collect();
    // What the next frame samples before writing it (a history): its last writer stores it.
    let next_frame = plan.sampled_before_written();
    for (i, pass) in plan.passes.iter_mut().enumerate() {
        let sky = if pass.kind == PassKind::FarField {
            [SKY[0], SKY[1], SKY[2], 0.0]
        } else {
            SKY
        };
        for u in pass.uses_mut() {
            let later = all_uses.iter().filter(|(j, v)| *j > i && v.overlaps(u));
            let mut kept_later = false;
            let mut replaced_later = false;
            for (_, v) in later {
                match v.access {
                    Access::Keep if !replaced_later => kept_later = true,
                    Access::Clear | Access::Overwrite => replaced_later = true,
                    Access::Keep => {}
                }
            }
            let sampled_next_frame = next_frame.contains(&u.attachment) && !replaced_later;
            let sampled_later = sampled_after[i].contains(&u.attachment) || sampled_next_frame;
            // Samplers read the depth alone: only a later pass that loads it needs the stencil.
            let loaded_later = kept_later;
            kept_later |= sampled_later;
            let read_by_frame_reader =
                plan.attachments[u.attachment].read_after_frame && !replaced_later;
            u.load = LoadOp::from_access(u.access);
            u.store = StoreOp::from_read_later(kept_later || read_by_frame_reader);
            let stencil = plan.attachments[u.attachment]
                .format
                .stencil_bytes_per_pixel()
                > 0;
            u.stencil_store = StoreOp::from_read_later(
                stencil && u.store == StoreOp::Store && (loaded_later || read_by_frame_reader),
            );
            let a = &plan.attachments[u.attachment];
            let working = if a.format.is_depth() {
                Layout::DepthStencilAttachment
            } else {
                Layout::ColorAttachment
            };
            (u.initial_layout, u.final_layout) =
                Layout::around(working, u.load, u.store, a.read_after_frame, sampled_later);
            // A runtime's compositor takes its swapchain images as colour attachments.
            if plan.external_output && u.final_layout == Layout::TransferSrc {
                u.final_layout = Layout::ColorAttachment;
            }
            // Reverse-Z: depth clears to the far plane, 0.
            u.clear = (u.load == LoadOp::Clear).then_some(if a.format.is_depth() {
                ClearValue::DepthStencil {
                    depth: 0.0,
                    stencil: 0,
                }
            } else {
                ClearValue::Color(sky)
            });
        }
    }
    let pairs: Vec<_> = plan.history_pairs().collect();
    for (id, a) in plan.attachments.iter_mut().enumerate() {
        let uses: Vec<&Use> = plan
            .passes
            .iter()
            .flat_map(|p| p.uses())
            .filter(|u| u.attachment == id)
            .collect();
        let loads: Vec<LoadOp> = uses.iter().map(|u| u.load).collect();
        let stores: Vec<StoreOp> = uses.iter().map(|u| u.store).collect();
        // Both images of a history pair are sampled: each on every other frame.
        a.sampled = plan.passes.iter().any(|p| p.samples.contains(&id))
            || pairs.iter().any(|h| h.contains(id));
        a.transient = !a.read_after_frame && !a.sampled && is_transient(&loads, &stores);
    }
}

/// Every step's stencil state from the steps its pass has, and a stencil-capable depth format
/// wherever a step tests or writes stencil.
pub(super) fn assign_stencil(plan: &mut FramePlan) {
    for pass in &mut plan.passes {
        assign_stencil_states(&mut pass.steps);
        if pass.steps.iter().any(|s| s.stencil().is_some()) {
            if let Some(depth) = pass.depth {
                plan.attachments[depth.attachment].format = Format::D32S8;
            }
        }
    }
}
