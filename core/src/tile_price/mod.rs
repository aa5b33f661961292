//! A tile GPU's price of a frame: a **formula**, not a measurement. Nothing here ran on an
//! Adreno; the inputs are measured or compiled elsewhere and combined by a stated rule:
//!
//! - the fragments each step shades and the triangles each pass draws, counted on a device that
//!   runs the frame (lavapipe's counting frame: the same scene, views and gaze);
//! - the instructions the tile GPU's own compiler made of each step's shaders (Mesa's turnip,
//!   `VK_KHR_pipeline_executable_properties`: the fragment shader per fragment, the vertex
//!   shader and the binning pass's vertex shader per vertex, NOPs included: they are issue
//!   slots);
//! - the bytes each pass moves to and from memory, by the plan's traffic formula (an upper
//!   bound: Adreno's framebuffer compression, UBWC, moves fewer).
//!
//! Per pass, the ALU bound is instructions ÷ (ALU lanes × clock) and the memory bound bytes ÷
//! bandwidth; the pass costs the larger (a roofline: the two overlap), and the frame the sum of
//! its passes and the display's read of the output. Ignored: latency the waves do not hide
//! (texture fetches, the sync stalls turnip estimates), the binning pass's fixed cost per bin,
//! fixed-function limits (rasteriser, blending, resolves on tile), cache hits. It is a lower
//! bound on time, for comparing frames with each other (ratios to stereo 4×), not a frame time.

mod work;

pub use work::{frame_work, PassWork, StepWork, WorkError};

/// A tile GPU as the price takes it: public figures, with their sources. Qualcomm publishes no
/// ALU count or shader clock for its Adrenos; the figures below are what public
/// specification tables give, and they disagree (the Adreno 650 is listed with 512, 768 and
/// 1024 ALUs). A ratio between two frames priced on one GPU depends only on its balance of ALU
/// rate to bandwidth, not on the absolute figures.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TileGpu {
    /// Its name, as `foveate` prints it.
    pub name: &'static str,
    /// The headsets that carry it.
    pub headsets: &'static str,
    /// FP32 ALU lanes (one instruction per lane per clock).
    pub alu_lanes: f64,
    /// The shader clock in MHz.
    pub clock_mhz: f64,
    /// Peak memory bandwidth in GB/s (10⁹ bytes a second).
    pub bandwidth_gb_s: f64,
    /// Where the figures come from.
    pub sources: &'static str,
}

/// The Adreno 650 of the Snapdragon XR2 and XR2+ Gen 1 (Quest 2, Quest Pro).
pub const ADRENO_650: TileGpu = TileGpu {
    name: "Adreno 650",
    headsets: "Quest 2, Quest Pro (Snapdragon XR2 / XR2+ Gen 1)",
    alu_lanes: 768.0,
    clock_mhz: 587.0,
    bandwidth_gb_s: 44.0,
    sources: "768 ALUs at 587 MHz (900 GFLOPS FP32): hmc-tech.com's Adreno 650 table; 587 MHz: \
              Notebookcheck, Qualcomm Adreno 650 (the Snapdragon 865's clock, which the XR2 \
              derives from); 44 GB/s: LPDDR5-5500 on a 64-bit bus, the Snapdragon 865's peak",
};

/// The Adreno 740 of the Snapdragon XR2 Gen 2 (Quest 3).
pub const ADRENO_740: TileGpu = TileGpu {
    name: "Adreno 740",
    headsets: "Quest 3 (Snapdragon XR2 Gen 2)",
    // Qualcomm and Meta: the XR2 Gen 2's GPU has "up to 2.5x" the XR2 Gen 1's peak; the
    // lanes below give 2.5 × the 650's ALU rate at the 8 Gen 2's 680 MHz.
    alu_lanes: 768.0 * 2.5 * 587.0 / 680.0,
    clock_mhz: 680.0,
    bandwidth_gb_s: 64.0,
    sources: "2.5x the XR2 Gen 1's GPU peak: Qualcomm and Meta at the XR2 Gen 2's launch \
              (2023-09, as reported by Trusted Reviews and Mixed); 680 MHz and 64 GB/s \
              (LPDDR5X-4200, 128-bit): the Snapdragon 8 Gen 2's Adreno 740 as primua.com lists it",
};

/// The tile GPUs foveate prices frames on.
pub const TILE_GPUS: [TileGpu; 2] = [ADRENO_650, ADRENO_740];

/// Which bound a pass's price is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Bound {
    /// Its instructions.
    Alu,
    /// Its bytes.
    Memory,
}

/// One pass's price.
#[derive(Clone, Debug, PartialEq)]
pub struct PassPrice {
    /// The pass's name, as the plan prints it.
    pub name: &'static str,
    /// Its instructions' time, ms.
    pub alu_ms: f64,
    /// Its bytes' time, ms.
    pub memory_ms: f64,
}

impl PassPrice {
    /// The pass's price: the larger bound.
    pub fn ms(&self) -> f64 {
        self.alu_ms.max(self.memory_ms)
    }

    /// Which bound it is.
    pub fn bound(&self) -> Bound {
        if self.alu_ms >= self.memory_ms {
            Bound::Alu
        } else {
            Bound::Memory
        }
    }
}

/// A frame's price on one tile GPU.
#[derive(Clone, Debug, PartialEq)]
pub struct FramePrice {
    /// The GPU it was priced on.
    pub gpu: TileGpu,
    /// Each pass's, in plan order.
    pub passes: Vec<PassPrice>,
    /// The display's read of the output, ms.
    pub display_read_ms: f64,
}

impl FramePrice {
    /// The frame's price: its passes' and the display's read.
    pub fn ms(&self) -> f64 {
        self.passes.iter().map(PassPrice::ms).sum::<f64>() + self.display_read_ms
    }
}

impl TileGpu {
    /// Instructions a second over every lane.
    pub fn instructions_per_second(&self) -> f64 {
        self.alu_lanes * self.clock_mhz * 1e6
    }

    /// The frame whose passes did `work`, the display then reading `display_bytes`.
    pub fn price(&self, work: &[PassWork], display_bytes: u64) -> FramePrice {
        let ms = |instructions: f64| instructions / self.instructions_per_second() * 1e3;
        let memory_ms = |bytes: u64| bytes as f64 / (self.bandwidth_gb_s * 1e9) * 1e3;
        FramePrice {
            gpu: *self,
            passes: work
                .iter()
                .map(|w| PassPrice {
                    name: w.name,
                    alu_ms: ms(w.instructions()),
                    memory_ms: memory_ms(w.bytes),
                })
                .collect(),
            display_read_ms: memory_ms(display_bytes),
        }
    }
}

#[cfg(test)]
mod tests;
