//! What a frame plan costs a tile GPU, from the plan alone: the memory its attachments need,
//! the samples its MSAA resolves average, and its external memory traffic. Estimates from the
//! plan, labelled so wherever they are printed; lavapipe cannot measure them.

use super::model::{AttachmentPlan, FramePlan};
use super::ops::{LoadOp, StoreOp};

impl FramePlan {
    /// Bytes of attachments that must be backed by memory (not transient).
    pub fn resident_bytes(&self) -> u64 {
        self.attachments
            .iter()
            .filter(|a| !a.transient)
            .map(AttachmentPlan::bytes)
            .sum()
    }

    /// Bytes of attachments that may live on tile only.
    pub fn transient_bytes(&self) -> u64 {
        self.attachments
            .iter()
            .filter(|a| a.transient)
            .map(AttachmentPlan::bytes)
            .sum()
    }

    /// Samples the frame's MSAA resolves average, over every in-pass resolve: the work a tile
    /// GPU does on tile (nearly free there) and lavapipe does in memory.
    pub fn resolved_samples(&self) -> u64 {
        self.passes
            .iter()
            .filter_map(|p| p.resolve.map(|r| (p.color, r)))
            .map(|(color, r)| {
                let a = &self.attachments[r.attachment];
                let samples = self.attachments[color.attachment].samples as u64;
                a.width as u64 * a.height as u64 * r.layer_count as u64 * samples
            })
            .sum()
    }

    /// Estimated external memory traffic per frame on a tile GPU: bytes loaded into tile
    /// memory, stored out of it, sampled by later passes, and read back as the output.
    pub fn external_traffic_bytes(&self) -> u64 {
        let attachment_traffic: u64 = self
            .passes
            .iter()
            .flat_map(|p| p.uses())
            .map(|u| {
                let a = &self.attachments[u.attachment];
                let bytes = a.layer_bytes() * u.layer_count as u64;
                let stencil = a.stencil_bytes() / a.layers as u64 * u.layer_count as u64;
                let loaded = if u.load == LoadOp::Load { bytes } else { 0 };
                let stored = match (u.store, u.stencil_store) {
                    (StoreOp::Store, StoreOp::Store) => bytes,
                    (StoreOp::Store, StoreOp::DontCare) => bytes - stencil,
                    (StoreOp::DontCare, _) => 0,
                };
                loaded + stored
            })
            .sum();
        // A sampler reads a depth/stencil image's depth alone.
        let sampled: u64 = self
            .passes
            .iter()
            .flat_map(|p| &p.samples)
            .map(|&i| self.attachments[i].bytes() - self.attachments[i].stencil_bytes())
            .sum();
        let read_back: u64 = self
            .outputs()
            .iter()
            .map(|&i| self.attachments[i].bytes())
            .sum();
        attachment_traffic + sampled + read_back
    }
}
