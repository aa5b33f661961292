//! A tile GPU's driver opened beside the device that renders, to price frames on it
//! (`foveate::tile_price`, a formula): the frame planned for the tile GPU, its pipelines
//! compiled there for their statistics, the fragments and triangles counted on the rendering
//! device. Used by `foveate price` and by `compare --price-device`.

use anyhow::{Context, Result};
use foveate::gpu::{Gpu, GpuOptions};
use foveate::plan::RenderConfig;
use foveate::render::{counting_frame, FrameStats, Renderer};
use foveate::scene::Scene;
use foveate::tile_price::{frame_work, FramePrice, PassWork, TileGpu, TILE_GPUS};

/// The tile GPU's device and the chip its price takes.
pub struct TilePricer {
    pub gpu: Gpu,
    pub chip: TileGpu,
}

/// What a frame costs on the tile GPU, and the work it was priced from.
pub struct Priced {
    pub price: FramePrice,
    pub work: Vec<PassWork>,
}

/// The rendering device (`options.device`, or the first device that is not the tile GPU's)
/// and the tile GPU's (`price_device`: an index or part of its name), both opened.
pub fn open(options: &GpuOptions, price_device: &str) -> Result<(Gpu, TilePricer)> {
    let listed = Gpu::list_devices()?;
    let is_tile = |d: &foveate::gpu::DeviceInfo| {
        price_device.parse::<usize>().ok() == Some(d.index)
            || d.name.to_lowercase().contains(&price_device.to_lowercase())
    };
    let tile = listed.iter().find(|d| is_tile(d)).with_context(|| {
        format!(
            "invalid price-device = {price_device}: no such device (devices: {}); run through scripts/adreno.sh",
            listed.iter().map(|d| d.name.as_str()).collect::<Vec<_>>().join(", ")
        )
    })?;
    let chip = *TILE_GPUS
        .iter()
        .find(|g| tile.name.contains(&g.name["Adreno ".len()..]))
        .with_context(|| {
            format!(
                "invalid price-device = {price_device}: {} is none of the tile GPUs foveate prices ({})",
                tile.name,
                TILE_GPUS.map(|g| g.name).join(", ")
            )
        })?;
    let runner = match &options.device {
        Some(d) => d.clone(),
        None => listed
            .iter()
            .find(|d| !is_tile(d) && d.unusable.is_none())
            .map(|d| d.index.to_string())
            .context("no device besides the tile GPU's to render and count on")?,
    };
    let open = |device: String| {
        Gpu::new(&GpuOptions {
            device: Some(device),
            ..options.clone()
        })
    };
    let gpu = open(tile.index.to_string())?;
    Ok((open(runner)?, TilePricer { gpu, chip }))
}

impl TilePricer {
    /// `config` as the tile GPU plans it, the fovea's layout made explicit: the rendering
    /// device counts this configuration, so that every step priced is a step counted
    /// (lavapipe's quirks may choose another layout by its own speed).
    pub fn as_planned_here(&self, scene: &Scene, config: &RenderConfig) -> Result<RenderConfig> {
        let plan = foveate::plan(scene, config, self.gpu.caps())?;
        Ok(RenderConfig {
            fovea_layout: plan
                .fovea_layout
                .as_ref()
                .map_or(config.fovea_layout, |c| c.layout),
            ..config.clone()
        })
    }

    /// The price of `config`'s frame: its fragments and triangles counted on `runner` with the
    /// gaze at `gaze` — `counted` where the frame it counted (`counted_plan`) has the tile GPU's
    /// fovea layout, else a counting frame of that layout.
    pub fn price(
        &self,
        runner: &Gpu,
        scene: &Scene,
        config: &RenderConfig,
        gaze: [glam::Vec2; 2],
        (counted, counted_plan): (&FrameStats, &foveate::plan::FramePlan),
    ) -> Result<Priced> {
        let config = RenderConfig {
            timestamps: false,
            ..self.as_planned_here(scene, config)?
        };
        let plan = foveate::plan(scene, &config, self.gpu.caps())?;
        let layout = |p: &foveate::plan::FramePlan| p.fovea_layout.as_ref().map(|c| c.layout);
        let recounted;
        let counted = if layout(&plan) == layout(counted_plan) {
            counted
        } else {
            recounted = counting_frame(runner, scene, &config, gaze, scene.head)?;
            &recounted
        };
        // Creating the renderer compiles every pipeline, capturing the compiler's statistics.
        let renderer = Renderer::new(&self.gpu, &plan, scene)?;
        let steps = renderer
            .layer()
            .shader_statistics()
            .with_context(|| format!("{} reports no shader statistics", self.gpu.info().name))?;
        let work = frame_work(&plan, &steps, counted)?;
        Ok(Priced {
            price: self.chip.price(&work, plan.display_read_bytes()),
            work,
        })
    }

    /// The lines that say what the price is, printed before it.
    pub fn describe(&self, runner: &Gpu) -> String {
        let c = &self.chip;
        format!(
            "rendering and counting on {}; compiling on {}; priced as the {} of the {}\nthe price is a formula: counted fragments and vertices x the compiler's instructions over {} ALU lanes at {} MHz, and the plan's bytes at {} GB/s; per pass the larger, summed",
            runner.info().name,
            self.gpu.info().name,
            c.name,
            c.headsets,
            c.alu_lanes.round(),
            c.clock_mhz,
            c.bandwidth_gb_s
        )
    }
}
