//! Where the commands' frames are judged (`--metric`): on the device that rendered them (the
//! GPU judge and `judge::GpuFlicker`, the default), or on the CPU (NVIDIA's reference FLIP and
//! `metrics::temporal::Flicker`, the oracles the GPU is tested against). Chosen once, for the
//! whole run.

use std::sync::OnceLock;

use foveate::gpu::Gpu;
use foveate::judge::GpuFlip;
use foveate::metrics::flip::CpuFlip;
use foveate::metrics::FlipMapper;

/// Where frames are judged.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, clap::ValueEnum)]
pub enum Metric {
    /// Compute passes on the Vulkan device that rendered the frames.
    #[default]
    Gpu,
    /// NVIDIA's reference C++ on the CPU (slow: the oracle).
    Cpu,
}

static CHOSEN: OnceLock<Metric> = OnceLock::new();

/// Sets the run's metric; the first call wins.
pub fn choose(metric: Metric) {
    let _ = CHOSEN.set(metric);
}

/// The run's metric.
pub fn chosen() -> Metric {
    CHOSEN.get().copied().unwrap_or_default()
}

/// A judge of the run's metric, on `gpu` when it is the GPU's.
pub fn flip_mapper(gpu: &Gpu) -> Box<dyn FlipMapper> {
    match chosen() {
        Metric::Gpu => Box::new(GpuFlip::new(gpu)),
        Metric::Cpu => Box::new(CpuFlip),
    }
}
