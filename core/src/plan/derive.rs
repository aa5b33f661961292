//! The derivation rules: from what passes declare about an attachment (its [`Access`]) and
//! who reads it afterwards, to Vulkan load/store ops and transient usage.

use std::fmt;

use super::model::{AttachmentId, Format, FramePlan, PassKind, Use, SKY};
use super::steps::assign_stencil_states;

/// What a pass declares about an attachment's contents when it starts using it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Access {
    /// Starts from a cleared value; earlier contents are irrelevant.
    Clear,
    /// Every pixel is overwritten (e.g. an MSAA resolve target); earlier contents irrelevant.
    Overwrite,
    /// Continues from the contents an earlier pass (or frame) left.
    Keep,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LoadOp {
    Clear,
    Load,
    DontCare,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StoreOp {
    Store,
    DontCare,
}

impl LoadOp {
    pub fn from_access(access: Access) -> Self {
        match access {
            Access::Clear => LoadOp::Clear,
            Access::Overwrite => LoadOp::DontCare,
            Access::Keep => LoadOp::Load,
        }
    }
}

impl StoreOp {
    /// Contents are stored only when someone reads them after the pass.
    pub fn from_read_later(read_later: bool) -> Self {
        if read_later {
            StoreOp::Store
        } else {
            StoreOp::DontCare
        }
    }
}

/// The layout an attachment is in when a pass starts or ends with it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Layout {
    /// Contents not needed: the driver may discard them.
    Undefined,
    ColorAttachment,
    DepthStencilAttachment,
    /// Ready for the copy that reads the frame's output back.
    TransferSrc,
    /// Ready to be sampled by a later pass.
    ShaderReadOnly,
}

impl Layout {
    /// Where a use starts and ends: loaded contents must already be in the working layout
    /// (otherwise `Undefined` lets the driver skip preserving them); stored contents end ready
    /// for whoever reads them next — the frame's readback, a later pass sampling them — and
    /// anything else stays in the working layout.
    pub fn around(
        working: Layout,
        load: LoadOp,
        store: StoreOp,
        read_after_frame: bool,
        sampled_later: bool,
    ) -> (Layout, Layout) {
        let initial = if load == LoadOp::Load {
            working
        } else {
            Layout::Undefined
        };
        let last = if read_after_frame && store == StoreOp::Store {
            Layout::TransferSrc
        } else if sampled_later {
            Layout::ShaderReadOnly
        } else {
            working
        };
        (initial, last)
    }
}

/// What a cleared attachment starts as.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ClearValue {
    /// Linear-light RGBA.
    Color([f32; 4]),
    /// Reverse-Z depth (0 is the far plane) and stencil.
    DepthStencil { depth: f32, stencil: u32 },
}

/// An attachment can live only on tile (transient, lazily allocated where the device offers
/// it) when no pass ever loads or stores it.
pub fn is_transient(loads: &[LoadOp], stores: &[StoreOp]) -> bool {
    !loads.contains(&LoadOp::Load) && !stores.contains(&StoreOp::Store)
}

impl fmt::Display for LoadOp {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            LoadOp::Clear => "CLEAR",
            LoadOp::Load => "LOAD",
            LoadOp::DontCare => "DONT_CARE",
        })
    }
}

impl fmt::Display for StoreOp {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            StoreOp::Store => "STORE",
            StoreOp::DontCare => "DONT_CARE",
        })
    }
}

impl fmt::Display for Layout {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Layout::Undefined => "UNDEFINED",
            Layout::ColorAttachment => "COLOR_ATTACHMENT",
            Layout::DepthStencilAttachment => "DEPTH_STENCIL_ATTACHMENT",
            Layout::TransferSrc => "TRANSFER_SRC",
            Layout::ShaderReadOnly => "SHADER_READ_ONLY",
        })
    }
}

impl fmt::Display for ClearValue {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ClearValue::Color([r, g, b, a]) => write!(f, "colour ({r}, {g}, {b}, {a})"),
            ClearValue::DepthStencil { depth, stencil } => {
                write!(f, "depth {depth}, stencil {stencil}")
            }
        }
    }
}

/// Fills in every use's store op and every attachment's transient flag from declared intent:
/// a use stores only if a later pass keeps its contents or the frame's reader needs them and no
/// later pass replaces them first.
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
            kept_later |= sampled_after[i].contains(&u.attachment);
            let read_by_frame_reader =
                plan.attachments[u.attachment].read_after_frame && !replaced_later;
            u.load = LoadOp::from_access(u.access);
            u.store = StoreOp::from_read_later(kept_later || read_by_frame_reader);
            let a = &plan.attachments[u.attachment];
            let working = if a.format.is_depth() {
                Layout::DepthStencilAttachment
            } else {
                Layout::ColorAttachment
            };
            (u.initial_layout, u.final_layout) = Layout::around(
                working,
                u.load,
                u.store,
                a.read_after_frame,
                sampled_after[i].contains(&u.attachment),
            );
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
    for (id, a) in plan.attachments.iter_mut().enumerate() {
        let uses: Vec<&Use> = plan
            .passes
            .iter()
            .flat_map(|p| p.uses())
            .filter(|u| u.attachment == id)
            .collect();
        let loads: Vec<LoadOp> = uses.iter().map(|u| u.load).collect();
        let stores: Vec<StoreOp> = uses.iter().map(|u| u.store).collect();
        a.sampled = plan.passes.iter().any(|p| p.samples.contains(&id));
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
