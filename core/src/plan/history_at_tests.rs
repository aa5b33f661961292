//! The periphery accumulated at its own texels
//! ([`HistoryAt::Periphery`](crate::foveation::HistoryAt::Periphery)): a pass of its own
//! between the scene passes and the output pass, its history at the periphery's size.

use super::tests::*;
use super::*;
use crate::foveation::{FoveationConfig, HistoryAt, HistoryFormat, TemporalConfig};
use crate::plan::pipeline::Constant;

fn accumulated(history_at: HistoryAt) -> RenderConfig {
    RenderConfig {
        foveation: foveated(true).foveation.map(|f| FoveationConfig {
            periphery_density: Some(0.25),
            periphery_msaa: Some(1),
            periphery_temporal: Some(TemporalConfig {
                history_at,
                ..Default::default()
            }),
            ..f
        }),
        fovea_layout: FoveaLayout::Auto,
        ..foveated(true)
    }
}

/// The accumulation pass samples what the output pass would have (the periphery, the fovea,
/// the history, this frame's and the frame before's periphery depth), writes the next history
/// beside its own image, and both are the periphery's size (128² here, of a 512² output);
/// the output pass then samples the accumulated image in the periphery's place and keeps no
/// history. Mutations: the history sized at the output, the output pass still sampling the
/// periphery's own image, or the next history written by the output pass, fail it.
#[test]
fn the_history_at_the_periphery_is_a_pass_of_its_own_at_the_periphery_size() {
    let at_output = planned(&accumulated(HistoryAt::Output));
    let plan = planned(&accumulated(HistoryAt::Periphery));
    let kinds: Vec<PassKind> = plan.passes.iter().map(|p| p.kind).collect();
    assert_eq!(
        kinds,
        [
            PassKind::Scene,
            PassKind::Scene,
            PassKind::Accumulate,
            PassKind::Output
        ]
    );
    let [periphery, fovea, accumulate, output] = &plan.passes[..] else {
        unreachable!()
    };
    let colour = |p: &PassPlan| p.resolve.unwrap_or(p.color).attachment;
    let pair = plan.history.expect("a history pair");
    let depths = plan.depth_history.expect("the periphery's depth as a pair");
    assert_eq!(
        accumulate.samples,
        [
            colour(periphery),
            colour(fovea),
            pair.read,
            depths.written,
            depths.read
        ],
        "what the output pass samples when it accumulates: {:?}",
        at_output.passes[2].samples
    );
    assert_eq!(accumulate.history.map(|h| h.attachment), Some(pair.written));
    assert_eq!(output.history, None);
    assert_eq!(output.samples, [accumulate.color.attachment, colour(fovea)]);
    let size = |id: AttachmentId| {
        let a = &plan.attachments[id];
        (a.width, a.height, a.layers)
    };
    let periphery_size = size(colour(periphery));
    assert_eq!(periphery_size, (128, 128, 2));
    for id in [pair.read, pair.written, accumulate.color.attachment] {
        assert_eq!(size(id), periphery_size, "{}", plan.attachments[id].name);
    }
    assert_eq!(size(output.color.attachment), (512, 512, 2));
    let (Step::Output(in_pass), Step::Output(composed)) = (&accumulate.steps[0], &output.steps[0])
    else {
        panic!("output steps");
    };
    assert!(in_pass.temporal && in_pass.periphery_only && !in_pass.lens);
    assert!(!composed.temporal && !composed.periphery_only);
    // Nothing kept at the output's pixels: the history is a sixteenth of the output's.
    let history_bytes = |p: &FramePlan| p.attachments[p.history.unwrap().read].bytes();
    assert_eq!(history_bytes(&at_output), 16 * history_bytes(&plan));
}

/// The bytes a tile GPU moves follow the history's size: the output's pixels move more than
/// the periphery's. Mutation: the history planned at the output's size in both, fails it.
#[test]
fn a_history_at_the_periphery_moves_fewer_bytes() {
    let bytes = |h| planned(&accumulated(h)).external_traffic_bytes();
    assert!(
        bytes(HistoryAt::Periphery) < bytes(HistoryAt::Output),
        "{} against {}",
        bytes(HistoryAt::Periphery),
        bytes(HistoryAt::Output)
    );
}

/// At a density of its own the history's pass and both its images are the screen at that
/// density (0.5 of 512² here: 256², between the periphery's 128² and the output's 512²), and
/// it moves more bytes than the history at the periphery's texels. Mutations: the density
/// ignored (the periphery's size), or applied to the periphery's size instead of the
/// screen's, fail it.
#[test]
fn a_history_at_a_density_of_its_own_sizes_its_pass_and_images() {
    let config = accumulated(HistoryAt::Periphery);
    let with_density = |d: f32| RenderConfig {
        foveation: config.foveation.map(|f| FoveationConfig {
            periphery_temporal: f.periphery_temporal.map(|t| TemporalConfig {
                history_density: Some(d),
                ..t
            }),
            ..f
        }),
        ..config.clone()
    };
    let plan = planned(&with_density(0.5));
    let pair = plan.history.expect("a history pair");
    let accumulate = plan.passes.iter().find(|p| p.kind == PassKind::Accumulate);
    let accumulate = accumulate.expect("an accumulation pass");
    for id in [pair.read, pair.written, accumulate.color.attachment] {
        let a = &plan.attachments[id];
        assert_eq!((a.width, a.height), (256, 256), "{}", a.name);
    }
    let bytes = |c: &RenderConfig| planned(c).external_traffic_bytes();
    assert!(bytes(&config) < bytes(&with_density(0.5)));
}

/// A history density is checked where it is given: within (0, 1], and only for a history in a
/// pass of its own. Mutation: either check left out fails it.
#[test]
fn a_history_density_out_of_range_or_without_its_pass_is_refused() {
    for (history_at, density) in [
        (HistoryAt::Periphery, 0.0),
        (HistoryAt::Periphery, 1.5),
        (HistoryAt::Periphery, f32::NAN),
        (HistoryAt::Output, 0.8),
    ] {
        let t = TemporalConfig {
            history_at,
            history_density: Some(density),
            ..Default::default()
        };
        let e = t.validate().expect_err("refused");
        assert!(e.to_string().contains("temporal_history_density"), "{e}");
    }
}

/// A luma history is one byte a pixel, a quarter of the colour history's bytes, at the same
/// size; the output pass is told to read it as luma. Mutations: the format left at 32 bits, or
/// the shader's constant left off, fail it.
#[test]
fn a_luma_history_is_one_byte_a_pixel() {
    let config = |history_format| RenderConfig {
        foveation: foveated(true).foveation.map(|f| FoveationConfig {
            periphery_temporal: Some(TemporalConfig {
                history_format,
                ..Default::default()
            }),
            ..f
        }),
        fovea_layout: FoveaLayout::Auto,
        ..foveated(true)
    };
    let (colour, luma) = (
        planned(&config(HistoryFormat::Colour)),
        planned(&config(HistoryFormat::Luma)),
    );
    let history = |p: &FramePlan| p.attachments[p.history.unwrap().written].clone();
    assert_eq!(history(&luma).format, Format::R8);
    assert_eq!(4 * history(&luma).bytes(), history(&colour).bytes());
    let luma_constant = |p: &FramePlan| {
        let output = p.passes.last().unwrap();
        (output.pipelines.iter()).any(|d| d.constants.contains(&(Constant::LumaHistory, 1)))
    };
    assert!(luma_constant(&luma) && !luma_constant(&colour));
}
