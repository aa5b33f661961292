//! The plan's attachments: the images a frame renders into, their formats, and each pass's use
//! of them with the load and store ops derived from intent.

use super::ops::{Access, AttachmentId, ClearValue, Layout, LoadOp, StoreOp};

/// Pixel formats the planner uses.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    /// Colour: 8-bit sRGB, so MSAA resolves and blending happen in linear light.
    Rgba8Srgb,
    /// Colour: 8-bit linear values (an output an engine or runtime takes as linear).
    Rgba8Unorm,
    /// Colour in linear half floats: an output an engine composes in linear light.
    Rgba16F,
    /// Colour in 10 bits a channel and 2 of alpha (`A2B10G10R10_UNORM_PACK32`, 32 bits a
    /// pixel): the periphery's temporal history, holding the square root of linear light so
    /// its steps stay finer than the display's down to the darks (small blends of new samples
    /// must not round away: the 6-bit mantissas of `B10G11R11_UFLOAT` lose them), at half the
    /// bytes of half floats; alpha 0 marks a pixel with no history, 2/3 one that holds what
    /// the fovea showed over the periphery's hole.
    Rgb10A2,
    /// One 8-bit channel (`R8_UNORM`): the periphery's luma history
    /// ([`HistoryFormat::Luma`](crate::foveation::HistoryFormat::Luma)), its code 0 a pixel
    /// with no history, 1 to 255 the square root of linear luma.
    R8,
    /// Reverse-Z depth without stencil.
    D32,
    /// Reverse-Z depth with stencil, only when an effect writes stencil masks.
    D32S8,
}

impl Format {
    /// Bytes one pixel of one sample takes in memory.
    pub fn bytes_per_pixel(self) -> u64 {
        match self {
            Format::Rgba8Srgb | Format::Rgba8Unorm | Format::Rgb10A2 | Format::D32 => 4,
            Format::Rgba16F => 8,
            Format::R8 => 1,
            // D32_SFLOAT_S8_UINT is commonly stored as 4 + 1 bytes (plus padding).
            Format::D32S8 => 5,
        }
    }

    /// Bytes per pixel of the stencil alone (what a depth/stencil image keeps beside its
    /// depth; a sampler reads the depth and not this).
    pub fn stencil_bytes_per_pixel(self) -> u64 {
        match self {
            Format::D32S8 => 1,
            _ => 0,
        }
    }

    /// Whether this is a depth (or depth/stencil) format.
    pub fn is_depth(self) -> bool {
        matches!(self, Format::D32 | Format::D32S8)
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
/// What an attachment holds.
pub enum AttachmentRole {
    /// Colour (possibly multisampled).
    Color,
    /// Depth, or depth and stencil.
    Depth,
    /// Single-sample target an MSAA colour attachment resolves into inside the pass.
    Resolve,
}

/// One image the frame renders into, and its fate.
#[derive(Clone, Debug, PartialEq)]
pub struct AttachmentPlan {
    /// Its name in the printout and in debug labels.
    pub name: &'static str,
    /// What it holds.
    pub role: AttachmentRole,
    /// Its format.
    pub format: Format,
    /// Samples per pixel (1 without MSAA).
    pub samples: u32,
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// Array layers: one per view it holds.
    pub layers: u32,
    /// Read after the frame (readback or presentation).
    pub read_after_frame: bool,
    /// Sampled by a later pass (a texture, not an attachment, there).
    pub sampled: bool,
    /// Never loaded nor stored by any pass: may live on tile only.
    pub transient: bool,
}

impl AttachmentPlan {
    /// Its size in memory: every layer and sample.
    pub fn bytes(&self) -> u64 {
        self.width as u64
            * self.height as u64
            * self.layers as u64
            * self.samples as u64
            * self.format.bytes_per_pixel()
    }

    /// Bytes of the stencil alone, in every layer and sample (0 without one).
    pub fn stencil_bytes(&self) -> u64 {
        self.bytes() / self.format.bytes_per_pixel() * self.format.stencil_bytes_per_pixel()
    }

    pub(super) fn layer_bytes(&self) -> u64 {
        self.bytes() / self.layers as u64
    }
}

/// A pass's use of (some layers of) an attachment, with the ops derived from intent.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Use {
    /// The attachment used.
    pub attachment: AttachmentId,
    /// The first layer used (a view's layer).
    pub base_layer: u32,
    /// How many layers, from `base_layer`.
    pub layer_count: u32,
    /// Read, written or both.
    pub access: Access,
    /// What the pass starts it with.
    pub load: LoadOp,
    /// Whether the pass keeps what it wrote.
    pub store: StoreOp,
    /// The same for a depth attachment's stencil: kept only when a later pass loads the
    /// attachment (sampling reads the depth alone, and the stencil masks are drawn anew in
    /// every pass that tests them). `DontCare` for a format without stencil.
    pub stencil_store: StoreOp,
    /// Layout at the pass's start and end (derived: [`Layout::around`]).
    pub initial_layout: Layout,
    /// Layout at the pass's end.
    pub final_layout: Layout,
    /// What a cleared use starts as; `None` unless `load` clears.
    pub clear: Option<ClearValue>,
}

impl Use {
    pub(super) fn new(
        attachment: AttachmentId,
        base_layer: u32,
        layer_count: u32,
        access: Access,
    ) -> Self {
        // Ops are placeholders until `derive_ops` has seen the whole frame.
        Self {
            attachment,
            base_layer,
            layer_count,
            access,
            load: LoadOp::from_access(access),
            store: StoreOp::DontCare,
            stencil_store: StoreOp::DontCare,
            initial_layout: Layout::Undefined,
            final_layout: Layout::Undefined,
            clear: None,
        }
    }

    pub(super) fn overlaps(&self, other: &Use) -> bool {
        self.attachment == other.attachment
            && self.base_layer < other.base_layer + other.layer_count
            && other.base_layer < self.base_layer + self.layer_count
    }
}
