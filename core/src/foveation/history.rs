//! Where the periphery's temporal history keeps its pixels and what it keeps of each: the
//! choices of [`TemporalConfig`](super::TemporalConfig) that set the history's size and format.

use crate::vocab::named_enum;

/// Where the accumulated periphery's history keeps its pixels.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum HistoryAt {
    /// The output's pixels, in the output pass: the jittered samples land all over each output
    /// pixel, so the history holds detail beyond the periphery's density (supersampled over
    /// time), at the price of a full-view history read and written every frame.
    Output,
    /// The periphery's own texels, in a pass of its own at the periphery's size before the
    /// output pass, which then upscales the accumulated periphery as it would a single frame:
    /// the periphery anti-aliased over time but no sharper than its density, for a history
    /// the density² of the output's pixels. With
    /// [`TemporalConfig::history_density`](super::TemporalConfig::history_density) the pass
    /// and its history are at that density instead, between the periphery's and the output's
    /// (as temporal upscalers keep theirs at their output, not the display's).
    Periphery,
}

named_enum!(HistoryAt, "history at", [
    HistoryAt::Output => "output",
    HistoryAt::Periphery => "periphery",
]);

/// What the periphery's history keeps of each pixel.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum HistoryFormat {
    /// Its colour: the square root of linear light in 10 bits a channel, and 2 bits saying
    /// what it holds (nothing, the accumulated periphery, what the fovea showed, where a mover
    /// lay): 32 bits a pixel.
    Colour,
    /// Its luma alone, in one byte (the square root of linear luma, rounded with a dither that
    /// changes every frame, so a small blend of a new sample is not rounded away on average);
    /// the chroma comes from each frame's periphery. A quarter of the colour history's bytes;
    /// it cannot tell what the fovea showed or where a mover lay from the accumulated
    /// periphery, so after a gaze jump the old hole starts from the periphery, and a mover's
    /// trail is clipped only where a mover lies now.
    Luma,
}

named_enum!(HistoryFormat, "history format", [
    HistoryFormat::Colour => "colour",
    HistoryFormat::Luma => "luma",
]);
