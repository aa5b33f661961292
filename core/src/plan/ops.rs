//! What a pass does to an image: the intent it declares ([`Access`]), the load and store ops and
//! layouts derived from it, clear values, and the barriers between touches of an image.
//! Vocabulary only: `derive` and `barriers` decide.

use std::fmt;

/// Index into the frame plan's attachments.
pub type AttachmentId = usize;

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
/// What a pass does with an attachment's contents as it begins (Vulkan's load op).
pub enum LoadOp {
    /// Cleared to the use's clear value.
    Clear,
    /// Loaded: the contents an earlier pass left (on a tile GPU, read from memory).
    Load,
    /// Undefined: the pass overwrites every pixel.
    DontCare,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
/// What a pass does with an attachment's contents as it ends (Vulkan's store op).
pub enum StoreOp {
    /// Stored: someone reads them later (on a tile GPU, written to memory).
    Store,
    /// Discarded: nobody reads them.
    DontCare,
}

impl LoadOp {
    /// The load op an access implies: cleared, overwritten (don't care) or kept (load).
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
    /// Being rendered to as colour.
    ColorAttachment,
    /// Being rendered to as depth and stencil.
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
    DepthStencil {
        /** Reverse-Z depth. */
        depth: f32,
        /** Stencil value. */
        stencil: u32,
    },
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

/// How a pass, or the frame's reader, touches an image.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Touch {
    /// Colour attachment or resolve target: written (and read where the pass loads it).
    ColourAttachment,
    /// Depth/stencil attachment: tested and written.
    DepthAttachment,
    /// Sampled by a fragment shader.
    Sampled,
    /// Copied out after the frame: read back, or blitted to a swapchain.
    ReadAfterFrame,
}

impl Touch {
    /// Whether this touch writes the attachment.
    pub fn writes(self) -> bool {
        matches!(self, Touch::ColourAttachment | Touch::DepthAttachment)
    }
}

/// One dependency: `from` (an earlier touch of `attachment`) done and visible before `to`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Barrier {
    /// The attachment.
    pub attachment: AttachmentId,
    /// The earlier touch, done before the barrier.
    pub from: Touch,
    /// The later touch, waiting for it.
    pub to: Touch,
}

/// A pass's barriers: those it waits on as it begins, those it signals as it ends.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct PassBarriers {
    /// Barriers the pass waits on as it begins.
    pub wait: Vec<Barrier>,
    /// Barriers the pass signals as it ends.
    pub signal: Vec<Barrier>,
}

impl fmt::Display for Touch {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Touch::ColourAttachment => "colour attachment",
            Touch::DepthAttachment => "depth attachment",
            Touch::Sampled => "sampled",
            Touch::ReadAfterFrame => "read after the frame",
        })
    }
}

impl fmt::Display for Barrier {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "#{} {} → {}", self.attachment, self.from, self.to)
    }
}
