/// What the device can do, as far as planning cares. Filled from Vulkan by
/// `gpu::Gpu::caps`; built by hand in tests so the planner is tested without a GPU.
#[derive(Clone, Debug, PartialEq)]
pub struct DeviceCaps {
    /// The device's name.
    pub device_name: String,
    /// `maxMultiviewViewCount`; 0 when multiview is unsupported.
    pub max_multiview_views: u32,
    /// Sample counts usable for both colour and depth attachments (bit n set = 2ⁿ samples).
    pub framebuffer_sample_counts: u32,
    /// `maxImageDimension2D`.
    pub max_image_dimension_2d: u32,
    /// `maxViewportDimensions` (the smaller of the two).
    pub max_viewport_dimension: u32,
    /// `viewportBoundsRange`.
    pub viewport_bounds: (f32, f32),
    /// Whether a memory type with `LAZILY_ALLOCATED` exists (tile GPUs; lavapipe has none).
    pub lazily_allocated_memory: bool,
    /// `fragmentStoresAndAtomics`: counting frames need it.
    pub fragment_stores_and_atomics: bool,
    /// `shaderClipDistance`: instanced stereo needs it.
    pub shader_clip_distance: bool,
    /// `depthClamp`: primitives are not clipped against the near and far planes.
    pub depth_clamp: bool,
    /// Timestamps on the graphics queue: frames are timed with them.
    pub timestamps: bool,
    /// `samplerAnisotropy` and `maxSamplerAnisotropy` (0 without the feature): lit materials
    /// sample anisotropically where offered, trilinearly otherwise.
    pub max_anisotropy: f32,
    /// `pipelineStatisticsQuery`: counting frames measure primitives per pass with it.
    pub pipeline_statistics: bool,
    /// `D32_SFLOAT_S8_UINT` as a depth-stencil attachment: stencil masks (the HMD mask,
    /// foveation's inset and outset masks) need it; a plan without them does not.
    pub depth_stencil: bool,
    /// `VK_KHR_depth_stencil_resolve` with `VK_KHR_create_renderpass2` enabled (core in Vulkan
    /// 1.2): a pass can resolve its multisampled depth to one sample on tile, as it resolves
    /// colour. An accumulated periphery with MSAA needs it (its reprojection reads one depth
    /// per pixel); an engine's device plans without it (foveate cannot see what it enabled).
    pub depth_resolve: bool,
    /// What its driver gets wrong.
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
            depth_stencil: true,
            depth_resolve: true,
            quirks: DriverQuirks::default(),
        }
    }

    /// Whether `samples` per pixel are usable for colour and depth alike.
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
/// tests driver names. Each quirk applies to the drivers and versions where it was measured
/// (`tests/e2e/quirks.rs` measures each on the driver it runs on and fails when the table
/// disagrees; CI runs it on lavapipe from Mesa 22.3 and 25.0).
///
/// Every field is read by the planner. (More lavapipe pitfalls need no workaround because
/// foveate avoids what they break: `FRAGMENT_SHADER_INVOCATIONS` counts whole raster blocks on
/// 22.3 (4.5–7× the shaded pixels; exact at 1× MSAA on 25.0), and an occlusion query in a
/// multiview pass reports the sum of all views in its first query, so the fragment counters
/// are atomics; 22.3's screen-space derivatives of world-mapped texture coordinates go wrong
/// along triangle edges (not 25.0's), so world-mapped textures take analytic gradients.)
#[derive(Clone, Debug, Default, PartialEq)]
pub struct DriverQuirks {
    /// An MSAA resolve inside a render pass into an attachment view whose base array layer is
    /// not 0 writes layer 0, from the multisampled image's layer 0 (lavapipe 22.3; fixed in
    /// 25.0). The planner gives two-pass stereo one image per eye instead of one layer per eye
    /// of a shared image; an engine's views drawn one pass each (below) resolve into an image
    /// of their own, copied into their layer by a pass after (`plan/split_views.rs`).
    pub layered_resolve_ignores_base_layer: bool,
    /// In a multiview pass, primitives the driver has to clip are rasterised into the first
    /// view's layer, whatever their view (lavapipe 22.3: every primitive crossing the viewport
    /// edge or the eye plane, drawn with the first view's per-primitive data; fixed in 25.0).
    /// The planner works around it with an emulated guard band, which is enough for foveate's
    /// own scenes (no mesh of theirs crosses an eye's plane), and draws an engine's scene passes
    /// one view at a time; the tests `lavapipe_multiview_clipping_quirk_is_real` and
    /// `an_engines_ground_plane_is_drawn_by_each_eyes_own_views` measure the bug itself. The
    /// same driver draws a mesh split into several draws differently from the mesh in one draw,
    /// so a multiview pass that culls keeps clustered meshes whole there.
    pub multiview_clipping_drops_views: bool,
    /// A multiview pass runs its views one after another, vertex work included (lavapipe 22.3
    /// and 25.0: a CPU rasteriser replays the draws per view; its pipeline statistics count
    /// each view's primitives). Splitting a 4-view pass into two 2-view passes then adds no
    /// per-view work, and each pass can skip what its views do not see; the planner's `auto`
    /// fovea layout reads it.
    pub multiview_runs_views_serially: bool,
    /// Anisotropic filtering is offered but runs hundreds of times slower than trilinear
    /// (lavapipe 22.3: 18 s against 42 ms for a lit 256² atrium frame; 25.0 takes no longer
    /// than trilinear). The planner samples lit materials trilinearly instead.
    pub anisotropic_filtering_is_slow: bool,
    /// A timestamp or query recorded *outside* a render pass, after a multiview pass, writes
    /// one query slot per view of that pass instead of one (lavapipe 25.0, not 22.3: the driver
    /// keeps the ended pass's view mask; a pool sized by the spec is overrun and the driver's
    /// worker thread crashes). The planner gives every query pool spare slots past its end.
    pub queries_after_multiview_span_views: bool,
}

impl DriverQuirks {
    /// The quirks of the driver with this Vulkan driver ID (`VkDriverId` as a raw value) and
    /// `driverInfo` string (Mesa states its release there: lavapipe's `driverVersion` is 1).
    pub fn for_driver(driver_id: i32, driver_info: &str) -> Self {
        const MESA_LLVMPIPE: i32 = 13;
        if driver_id != MESA_LLVMPIPE {
            return Self::default();
        }
        // Measured on 22.3.6 and 25.0.7 (tests/e2e/quirks.rs). Releases between them were not
        // measured and keep every workaround: each is harmless where the bug is absent. A
        // release we cannot read is taken to be a new one.
        let mesa = mesa_release(driver_info).unwrap_or((u32::MAX, 0));
        let before_25 = mesa < (25, 0);
        Self {
            layered_resolve_ignores_base_layer: before_25,
            multiview_clipping_drops_views: before_25,
            multiview_runs_views_serially: true,
            anisotropic_filtering_is_slow: before_25,
            queries_after_multiview_span_views: mesa >= (23, 0),
        }
    }

    /// Every quirk by name, whether it applies, and what foveate does about it: for
    /// `foveate devices` and the log.
    pub fn listing(&self) -> [(&'static str, bool, &'static str); 5] {
        // Destructured whole, so that a new field does not compile until it is listed here.
        let &Self {
            layered_resolve_ignores_base_layer,
            multiview_clipping_drops_views,
            multiview_runs_views_serially,
            anisotropic_filtering_is_slow,
            queries_after_multiview_span_views,
        } = self;
        [
            (
                "multiview clipping drops views",
                multiview_clipping_drops_views,
                "guard band on multiview passes; an engine's scene passes draw one view each",
            ),
            (
                "layered resolve ignores base layer",
                layered_resolve_ignores_base_layer,
                "two-pass stereo renders one image per eye; an engine's view passes resolve alone, then copy",
            ),
            (
                "multiview runs views serially",
                multiview_runs_views_serially,
                "auto fovea layout may split the views into two passes",
            ),
            (
                "anisotropic filtering is slow",
                anisotropic_filtering_is_slow,
                "lit materials sampled trilinearly",
            ),
            (
                "queries after a multiview pass span its views",
                queries_after_multiview_span_views,
                "query pools get spare slots",
            ),
        ]
    }
}

/// The (major, minor) release in a Mesa driver's `driverInfo`: "Mesa 25.0.7-2~bpo12+1 (LLVM
/// 15.0.6)" is (25, 0).
fn mesa_release(driver_info: &str) -> Option<(u32, u32)> {
    let version = driver_info
        .split_whitespace()
        .skip_while(|w| *w != "Mesa")
        .nth(1)?;
    let mut parts = version.split(|c: char| !c.is_ascii_digit());
    Some((parts.next()?.parse().ok()?, parts.next()?.parse().ok()?))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn mesa_releases_are_read_from_driver_info() {
        for (info, release) in [
            ("Mesa 22.3.6 (LLVM 15.0.6)", Some((22, 3))),
            ("Mesa 25.0.7-2~bpo12+1 (LLVM 15.0.6)", Some((25, 0))),
            ("Mesa 24.2.8-1ubuntu1~24.04.1 (LLVM 19.1.1)", Some((24, 2))),
            ("Mesa 25.3.0-devel (git-1a2b3c4d)", Some((25, 3))),
            ("NVIDIA 550.54", None),
            ("Mesa", None),
            ("Mesa x.y", None),
        ] {
            assert_eq!(mesa_release(info), release, "{info}");
        }
    }

    /// Each quirk follows the release it was measured on; releases between 22.3 and 25.0 keep
    /// every workaround; an unreadable release counts as new (the workarounds are harmless, the
    /// crash is not); other drivers have none of lavapipe's quirks. Mutation: any release bound
    /// moved (25.0 → 26.0, 23.0 → 26.0) fails it.
    #[test]
    fn quirks_follow_the_driver_and_its_release() {
        const LLVMPIPE: i32 = 13;
        let lavapipe = |info| DriverQuirks::for_driver(LLVMPIPE, info);
        let mesa_22 = lavapipe("Mesa 22.3.6 (LLVM 15.0.6)");
        assert!(mesa_22.multiview_clipping_drops_views);
        assert!(mesa_22.layered_resolve_ignores_base_layer);
        assert!(mesa_22.anisotropic_filtering_is_slow);
        assert!(mesa_22.multiview_runs_views_serially);
        assert!(!mesa_22.queries_after_multiview_span_views);
        let mesa_24 = lavapipe("Mesa 24.2.8-1ubuntu1~24.04.1 (LLVM 19.1.1)");
        assert!(mesa_24.listing().iter().all(|&(_, applies, _)| applies));
        let mesa_25 = lavapipe("Mesa 25.0.7-2~bpo12+1 (LLVM 15.0.6)");
        assert!(mesa_25.queries_after_multiview_span_views);
        assert!(mesa_25.multiview_runs_views_serially);
        assert!(!mesa_25.multiview_clipping_drops_views);
        assert!(!mesa_25.layered_resolve_ignores_base_layer);
        assert!(!mesa_25.anisotropic_filtering_is_slow);
        assert_eq!(lavapipe("llvmpipe, release unknown"), mesa_25);
        const NVIDIA: i32 = 4;
        assert_eq!(
            DriverQuirks::for_driver(NVIDIA, "550.54"),
            DriverQuirks::default()
        );
    }
}
