/// What the device can do, as far as planning cares. Filled from Vulkan by
/// `gpu::Gpu::caps`; built by hand in tests so the planner is tested without a GPU.
#[derive(Clone, Debug, PartialEq)]
pub struct DeviceCaps {
    pub device_name: String,
    /// `maxMultiviewViewCount`; 0 when multiview is unsupported.
    pub max_multiview_views: u32,
    /// Sample counts usable for both colour and depth attachments (bit n set = 2ⁿ samples).
    pub framebuffer_sample_counts: u32,
    pub max_image_dimension_2d: u32,
    /// `maxViewportDimensions` (the smaller of the two).
    pub max_viewport_dimension: u32,
    /// `viewportBoundsRange`.
    pub viewport_bounds: (f32, f32),
    /// Whether a memory type with `LAZILY_ALLOCATED` exists (tile GPUs; lavapipe has none).
    pub lazily_allocated_memory: bool,
    pub fragment_stores_and_atomics: bool,
    pub shader_clip_distance: bool,
    /// `depthClamp`: primitives are not clipped against the near and far planes.
    pub depth_clamp: bool,
    pub timestamps: bool,
    /// `samplerAnisotropy` and `maxSamplerAnisotropy` (0 without the feature): lit materials
    /// sample anisotropically where offered, trilinearly otherwise.
    pub max_anisotropy: f32,
    /// `pipelineStatisticsQuery`: counting frames measure primitives per pass with it.
    pub pipeline_statistics: bool,
    pub quirks: DriverQuirks,
}

impl DeviceCaps {
    /// A capable tile-GPU-like device without quirks (4 views, 1× and 4× MSAA, lazily
    /// allocated memory), for planning and recording without a GPU: tests and examples.
    pub fn generic() -> Self {
        DeviceCaps {
            device_name: "generic device".into(),
            max_multiview_views: 4,
            framebuffer_sample_counts: 0b101, // 1 and 4 samples
            max_image_dimension_2d: 8192,
            max_viewport_dimension: 8192,
            viewport_bounds: (-16384.0, 16384.0),
            lazily_allocated_memory: true,
            fragment_stores_and_atomics: true,
            shader_clip_distance: true,
            depth_clamp: true,
            timestamps: true,
            max_anisotropy: 16.0,
            pipeline_statistics: true,
            quirks: DriverQuirks::default(),
        }
    }

    pub fn supports_samples(&self, samples: u32) -> bool {
        samples.is_power_of_two() && self.framebuffer_sample_counts & samples != 0
    }

    /// Supported sample counts, ascending.
    pub fn sample_counts(&self) -> Vec<u32> {
        (0..7)
            .map(|b| 1u32 << b)
            .filter(|s| self.framebuffer_sample_counts & s != 0)
            .collect()
    }
}

/// Everything foveate knows a driver gets wrong or lacks, in one place, so that no other code
/// tests driver names.
#[derive(Clone, Debug, Default, PartialEq)]
///
/// Every field is read by the planner. (Two more lavapipe pitfalls need no workaround because
/// foveate avoids what they break: `FRAGMENT_SHADER_INVOCATIONS` counts whole raster blocks, and
/// an occlusion query in a multiview pass reports the sum of all views in its first query; the
/// fragment counters are atomics instead.)
pub struct DriverQuirks {
    /// An MSAA resolve inside a render pass into an attachment view whose base array layer is
    /// not 0 writes layer 0 (lavapipe, Mesa 22.3). The planner gives two-pass stereo one image
    /// per eye instead of one layer per eye of a shared image.
    pub layered_resolve_ignores_base_layer: bool,
    /// In a multiview pass, primitives the driver has to clip are rasterised into the first
    /// view's layer, whatever their view (lavapipe, Mesa 22.3: every primitive crossing the
    /// viewport edge or the eye plane). The planner works around it with an emulated guard
    /// band; the test `lavapipe_multiview_clipping_quirk_is_real` measures the bug itself.
    pub multiview_clipping_drops_views: bool,
    /// A multiview pass runs its views one after another, vertex work included (lavapipe: a
    /// CPU rasteriser replays the draws per view). Splitting a 4-view pass into two 2-view
    /// passes then adds no per-view work, and each pass can skip what its views do not see;
    /// the planner's `auto` fovea layout reads it.
    pub multiview_runs_views_serially: bool,
    /// Anisotropic filtering is offered but runs hundreds of times slower than trilinear
    /// (lavapipe, Mesa 22.3: 18 s against 42 ms for a lit 256² atrium frame). The planner
    /// samples lit materials trilinearly instead.
    pub anisotropic_filtering_is_slow: bool,
}

impl DriverQuirks {
    /// The quirks of the driver with this Vulkan driver ID (`VkDriverId` as a raw value).
    pub fn for_driver_id(driver_id: i32) -> Self {
        const MESA_LLVMPIPE: i32 = 13;
        let lavapipe = driver_id == MESA_LLVMPIPE;
        Self {
            layered_resolve_ignores_base_layer: lavapipe,
            multiview_clipping_drops_views: lavapipe,
            multiview_runs_views_serially: lavapipe,
            anisotropic_filtering_is_slow: lavapipe,
        }
    }
}
