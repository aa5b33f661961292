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

/// Each named row's configuration at its sample count; priced, with the fovea's layout the
/// tile GPU's plan chose.
pub(super) fn configs(
    named: &[(String, u32, RenderConfig)],
    pricer: Option<&TilePricer>,
    scene: &Scene,
) -> Result<Vec<RenderConfig>> {
    named
        .iter()
        .map(|(_, msaa, c)| {
            let config = RenderConfig {
                msaa: *msaa,
                ..c.clone()
            };
            match pricer {
                Some(p) => p.as_planned_here(scene, &config),
                None => Ok(config),
            }
        })
        .collect()
}

/// Each judged row's price and the reference's (ms), in row order; none unpriced.
pub(super) fn prices(
    pricer: Option<&TilePricer>,
    scene: &Scene,
    reference: &Measured,
    judged: &[Judged],
    configs: &[RenderConfig],
) -> Result<Vec<(f64, f64)>> {
    let Some(p) = pricer else {
        return Ok(Vec::new());
    };
    let price = |m: &Measured, config: &RenderConfig| -> Result<f64> {
        Ok(p.price(scene, config, &m.counts)?.price.ms())
    };
    let base = price(reference, &configs[0])?;
    println!("the reference's price on the {}: {base:.3} ms", p.chip.name);
    judged
        .iter()
        .zip(&configs[1..])
        .map(|(j, config)| Ok((price(&j.measured, config)?, base)))
        .collect()
}
