//! `compare --price-device`: every row priced on a tile GPU (`crate::tile_pricer`), beside its
//! time on the device that renders it.

use anyhow::Result;
use foveate::gpu::{Gpu, GpuOptions};
use foveate::plan::RenderConfig;
use foveate::scene::Scene;

use crate::side_by_side::{Judged, Measured};
use crate::tile_pricer::{Priced, TilePricer};
use foveate::tile_price::PassWork;

/// The rendering device, and the tile GPU's where `price_device` names one.
pub(super) fn devices(
    options: &GpuOptions,
    price_device: Option<&str>,
) -> Result<(Gpu, Option<TilePricer>)> {
    Ok(match price_device {
        None => (Gpu::new(options)?, None),
        Some(name) => {
            let (gpu, pricer) = crate::tile_pricer::open(options, name)?;
            println!("{}", pricer.describe(&gpu));
            (gpu, Some(pricer))
        }
    })
}

/// One row's price on the tile GPU, beside the reference's.
pub(super) struct RowPrice {
    /// The row's price, ms.
    pub ms: f64,
    /// The reference's, ms.
    pub reference_ms: f64,
    /// The row's ALU and memory bounds summed over its passes (the display's read in the
    /// memory), ms.
    pub alu_ms: f64,
    pub memory_ms: f64,
    /// Instructions its shaders ran, by the tile GPU's compiler's counts × the fragments and
    /// vertices counted.
    pub instructions: f64,
}

/// Each judged row's price, in row order; none unpriced. `configs`: the reference's and the
/// rows', as measured; `gaze`: both eyes' gaze.
pub(super) fn prices(
    (runner, pricer): (&Gpu, Option<&TilePricer>),
    scene: &Scene,
    gaze: glam::Vec2,
    (reference, judged): (&Measured, &[Judged]),
    configs: &[RenderConfig],
) -> Result<Vec<RowPrice>> {
    let Some(p) = pricer else {
        return Ok(Vec::new());
    };
    let price = |m: &Measured, config: &RenderConfig| -> Result<Priced> {
        p.price(runner, scene, config, [gaze; 2], (&m.counts, &m.plan))
    };
    let base = price(reference, &configs[0])?.price.ms();
    println!("the reference's price on the {}: {base:.3} ms", p.chip.name);
    judged
        .iter()
        .zip(&configs[1..])
        .map(|(j, config)| {
            let Priced { price, work } = price(&j.measured, config)?;
            Ok(RowPrice {
                ms: price.ms(),
                reference_ms: base,
                alu_ms: price.passes.iter().map(|p| p.alu_ms).sum(),
                memory_ms: price.passes.iter().map(|p| p.memory_ms).sum::<f64>()
                    + price.display_read_ms,
                instructions: work.iter().map(PassWork::instructions).sum(),
            })
        })
        .collect()
}
