//! `compare --price-device`: every row priced on a tile GPU (`crate::tile_pricer`), beside its
//! time on the device that renders it.

use anyhow::Result;
use foveate::gpu::{Gpu, GpuOptions};
use foveate::plan::RenderConfig;
use foveate::scene::Scene;

use crate::side_by_side::{Judged, Measured};
use crate::tile_pricer::TilePricer;

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

/// Each judged row's price and the reference's (ms), in row order; none unpriced. `configs`:
/// the reference's and the rows', as measured; `gaze`: both eyes' gaze.
pub(super) fn prices(
    (runner, pricer): (&Gpu, Option<&TilePricer>),
    scene: &Scene,
    gaze: glam::Vec2,
    (reference, judged): (&Measured, &[Judged]),
    configs: &[RenderConfig],
) -> Result<Vec<(f64, f64)>> {
    let Some(p) = pricer else {
        return Ok(Vec::new());
    };
    let price = |m: &Measured, config: &RenderConfig| -> Result<f64> {
        let counted = (&m.counts, &m.plan);
        Ok(p.price(runner, scene, config, [gaze; 2], counted)?
            .price
            .ms())
    };
    let base = price(reference, &configs[0])?;
    println!("the reference's price on the {}: {base:.3} ms", p.chip.name);
    judged
        .iter()
        .zip(&configs[1..])
        .map(|(j, config)| Ok((price(&j.measured, config)?, base)))
        .collect()
}
