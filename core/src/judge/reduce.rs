//! What a judgement brings back: each judged pixel's region goes up, the per-pixel figures are
//! reduced to histograms on the device (`shaders/flip_histogram.comp`, `shaders/flicker.comp`,
//! the bins of [`ErrorHistogram`]), and only the histograms, and FLIP's maps when asked for,
//! come back.

use ash::vk;

use crate::gpu::{access, memory_barrier, Buffer, Gpu, GpuError, MemoryLocation};
use crate::metrics::{ErrorHistogram, EyePixels, Region, HISTOGRAM_BINS};

/// A pixel's label for a pixel the lens hides (the regions are 0, 1, 2 in `Region::ALL`'s
/// order).
const HIDDEN: u8 = 3;

/// The buffers of the reduction: labels up, counts on the device and back, maps back.
pub(super) struct Reduction {
    /// Each pixel's region as a byte, four to a word.
    pub(super) labels: Buffer,
    /// The histograms' counts, filled by atomics.
    pub(super) counts: Buffer,
    counts_back: Buffer,
    /// Both maps (FLIP, eccentricity-aware), interleaved, when asked for; made the first time.
    maps_back: Option<Buffer>,
    /// Pixels per map (one eye's).
    pixels: u64,
    histograms: usize,
}

impl Reduction {
    /// The buffers for `labelled` pixels' labels and `histograms` histograms.
    pub(super) fn new(gpu: &Gpu, labelled: u64, histograms: usize) -> Result<Self, GpuError> {
        use vk::BufferUsageFlags as Usage;
        let count_bytes = 4 * (histograms * (HISTOGRAM_BINS + 1)) as u64;
        let storage = Usage::STORAGE_BUFFER;
        Ok(Reduction {
            labels: Buffer::new(
                gpu,
                "flip labels",
                labelled.div_ceil(4) * 4,
                storage,
                MemoryLocation::CpuToGpu,
            )?,
            counts: Buffer::new(
                gpu,
                "flip histograms",
                count_bytes,
                storage | Usage::TRANSFER_SRC | Usage::TRANSFER_DST,
                MemoryLocation::GpuOnly,
            )?,
            counts_back: Buffer::new(
                gpu,
                "flip histograms read back",
                count_bytes,
                Usage::TRANSFER_DST,
                MemoryLocation::GpuToCpu,
            )?,
            maps_back: None,
            pixels: labelled,
            histograms,
        })
    }

    /// Writes each pixel's label, eye after eye: its region, or hidden.
    pub(super) fn upload_labels(&mut self, eyes: &[&EyePixels]) {
        let labels: Vec<u8> = (eyes.iter().flat_map(|e| &e.pixels))
            .map(|p| p.map_or(HIDDEN, |d| region_index(d.region)))
            .collect();
        self.labels.write(&labels);
    }

    /// Makes the buffer the maps come back in, if it is not there yet.
    pub(super) fn want_maps(&mut self, gpu: &Gpu) -> Result<(), GpuError> {
        if self.maps_back.is_none() {
            let bytes = 8 * self.pixels;
            let usage = vk::BufferUsageFlags::TRANSFER_DST;
            let buffer = Buffer::new(
                gpu,
                "flip maps read back",
                bytes,
                usage,
                MemoryLocation::GpuToCpu,
            )?;
            self.maps_back = Some(buffer);
        }
        Ok(())
    }

    /// Records clearing the counts, before the histogram pass adds to them.
    pub(super) fn record_clear(&self, device: &ash::Device, cmd: vk::CommandBuffer) {
        // SAFETY: `cmd` is recording; the buffer outlives the submission.
        unsafe {
            device.cmd_fill_buffer(cmd, self.counts.raw, 0, vk::WHOLE_SIZE, 0);
            memory_barrier(
                device,
                cmd,
                access::TRANSFER_WRITE,
                access::COMPUTE_READ_WRITE,
            );
        }
    }

    /// Records copying back what the host reads: the counts if `counts`, and `maps` if given
    /// (after [`Reduction::want_maps`]).
    pub(super) fn record_read_back(
        &self,
        device: &ash::Device,
        cmd: vk::CommandBuffer,
        counts: bool,
        maps: Option<&Buffer>,
    ) {
        let copy = |from: &Buffer, to: &Buffer| {
            let region = [vk::BufferCopy::default().size(to.size.min(from.size))];
            // SAFETY: `cmd` is recording; both buffers outlive the submission.
            unsafe { device.cmd_copy_buffer(cmd, from.raw, to.raw, &region) };
        };
        // SAFETY: `cmd` is recording.
        unsafe {
            memory_barrier(device, cmd, access::COMPUTE_WRITE, access::TRANSFER_READ);
        }
        if counts {
            copy(&self.counts, &self.counts_back);
        }
        if let (Some(maps), Some(back)) = (maps, &self.maps_back) {
            copy(maps, back);
        }
        // SAFETY: `cmd` is recording; the host reads after the fence.
        unsafe {
            memory_barrier(device, cmd, access::TRANSFER_WRITE, access::HOST_READ);
        }
    }

    /// The histograms read back, in the order the shader counts them.
    pub(super) fn histograms(&mut self) -> Vec<ErrorHistogram> {
        let counts = (self.counts_back).read_u32s(self.histograms * (HISTOGRAM_BINS + 1));
        counts
            .chunks_exact(HISTOGRAM_BINS + 1)
            .map(ErrorHistogram::from_counts)
            .collect()
    }

    /// The maps read back by the last judgement that wanted them (FLIP, then
    /// eccentricity-aware).
    pub(super) fn maps(&self) -> Option<(Vec<f32>, Vec<f32>)> {
        let bytes = self.maps_back.as_ref()?.mapped_slice();
        let value = |i: usize| f32::from_le_bytes(bytes[4 * i..4 * i + 4].try_into().unwrap());
        let pixels = self.pixels as usize;
        Some((
            (0..pixels).map(|i| value(2 * i)).collect(),
            (0..pixels).map(|i| value(2 * i + 1)).collect(),
        ))
    }
}

/// A region's label.
fn region_index(region: Region) -> u8 {
    Region::ALL.iter().position(|&r| r == region).unwrap_or(0) as u8
}
