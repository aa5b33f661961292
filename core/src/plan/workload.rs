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
    /// memory, stored out of it, sampled by later passes, and read back as the output — the
    /// sum of [`FramePlan::attachment_traffic`].
    pub fn external_traffic_bytes(&self) -> u64 {
        self.attachment_traffic()
            .iter()
            .map(AttachmentTraffic::total)
            .sum()
    }

    /// Each attachment's share of [`FramePlan::external_traffic_bytes`], by attachment index:
    /// its bytes loaded and stored by the passes that draw into it, sampled by the passes that
    /// read it, and read back as the output (a formula from the plan).
    pub fn attachment_traffic(&self) -> Vec<AttachmentTraffic> {
        let mut traffic = vec![AttachmentTraffic::default(); self.attachments.len()];
        for u in self.passes.iter().flat_map(|p| p.uses()) {
            let a = &self.attachments[u.attachment];
            let bytes = a.layer_bytes() * u.layer_count as u64;
            let stencil = a.stencil_bytes() / a.layers as u64 * u.layer_count as u64;
            let t = &mut traffic[u.attachment];
            if u.load == LoadOp::Load {
                t.loaded += bytes;
            }
            t.stored += match (u.store, u.stencil_store) {
                (StoreOp::Store, StoreOp::Store) => bytes,
                (StoreOp::Store, StoreOp::DontCare) => bytes - stencil,
                (StoreOp::DontCare, _) => 0,
            };
        }
        // A sampler reads a depth/stencil image's depth alone.
        for &i in self.passes.iter().flat_map(|p| &p.samples) {
            let a = &self.attachments[i];
            traffic[i].sampled += a.bytes() - a.stencil_bytes();
        }
        for &i in self.outputs().iter() {
            traffic[i].read_back += self.attachments[i].bytes();
        }
        traffic
    }
}

impl FramePlan {
    /// Each pass's share of [`FramePlan::external_traffic_bytes`], in plan order: the bytes it
    /// loads into tile memory, stores out of it and samples from earlier passes (the display's
    /// read of the output is no pass's). A formula from the plan, as that one.
    pub fn pass_traffic_bytes(&self) -> Vec<u64> {
        self.passes
            .iter()
            .map(|p| {
                let drawn: u64 = p
                    .uses()
                    .map(|u| {
                        let a = &self.attachments[u.attachment];
                        let bytes = a.layer_bytes() * u.layer_count as u64;
                        let stencil = a.stencil_bytes() / a.layers as u64 * u.layer_count as u64;
                        let loaded = if u.load == LoadOp::Load { bytes } else { 0 };
                        loaded
                            + match (u.store, u.stencil_store) {
                                (StoreOp::Store, StoreOp::Store) => bytes,
                                (StoreOp::Store, StoreOp::DontCare) => bytes - stencil,
                                (StoreOp::DontCare, _) => 0,
                            }
                    })
                    .sum();
                let sampled: u64 = p
                    .samples
                    .iter()
                    .map(|&i| self.attachments[i].bytes() - self.attachments[i].stencil_bytes())
                    .sum();
                drawn + sampled
            })
            .collect()
    }

    /// Bytes the display reads of the frame's output (by the plan's formula).
    pub fn display_read_bytes(&self) -> u64 {
        self.outputs()
            .iter()
            .map(|&i| self.attachments[i].bytes())
            .sum()
    }
}

/// One attachment's external memory traffic per frame on a tile GPU, in bytes: an estimate by
/// the plan's formula ([`FramePlan::attachment_traffic`]), not a measurement.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct AttachmentTraffic {
    /// Loaded into tile memory at the start of the passes that draw into it.
    pub loaded: u64,
    /// Stored out of tile memory at their end (a depth's stencil only where it is kept).
    pub stored: u64,
    /// Read by the passes that sample it (a depth image's depth alone).
    pub sampled: u64,
    /// Read back after the frame (the output).
    pub read_back: u64,
}

impl AttachmentTraffic {
    /// Every byte it moves.
    pub fn total(&self) -> u64 {
        self.loaded + self.stored + self.sampled + self.read_back
    }
}
