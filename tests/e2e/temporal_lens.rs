//! Temporal accumulation through the lens: the history is kept at the display's pixels, so
//! finding where a point lay in the frame before means inverting the lens's polynomial there.

use foveate::foveation::TemporalConfig;
use foveate::plan::{OutputStage, RenderConfig, Resolution};
use foveate::scene::atrium_scene;
use foveate::view::Eye;
use glam::Vec2;

use super::foveation::Blend;
use super::temporal::{box_down, config, periphery_error, render_sequence, turning};
use foveate_tests::gpu;

const SCREEN: u32 = 128;

fn through_the_lens(temporal: Option<TemporalConfig>) -> RenderConfig {
    RenderConfig {
        output: OutputStage::Lens,
        ..config(SCREEN, temporal)
    }
}

/// After half a second of a head turning 20°/s, the periphery accumulated through the lens lies
/// closer to the supersampled reference (the display's image at 4× the resolution,
/// box-filtered) than the bilinear periphery does: each point's history is found where the
/// frame before's display showed it. Mutation run: the lens inversion started at this pixel's
/// own display radius and never stepped (the head's motion lost across the lens) fails it.
#[test]
fn a_turning_history_is_found_through_the_lens() {
    let gpu = gpu();
    let scene = atrium_scene();
    let turn = turning(&scene);
    let last = turn[turn.len() - 1];
    let big = RenderConfig {
        foveation: None,
        resolution: Some(Resolution::square(SCREEN * 4)),
        ..through_the_lens(None)
    };
    let (_, reference) = render_sequence(&gpu, &scene, &big, &[last], |_| true);
    let reference = Eye::BOTH.map(|e| box_down(reference[0].eye(e), 4));
    let blend = Blend::of(&gpu, &through_the_lens(None), Vec2::ZERO);
    let region = Eye::BOTH.map(|e| {
        (0..SCREEN)
            .flat_map(|y| (0..SCREEN).map(move |x| (x, y)))
            .map(|(x, y)| blend.periphery_only(e, x, y))
            .collect::<Vec<bool>>()
    });
    let error = |temporal: Option<TemporalConfig>, poses: &[(glam::Mat4, Vec2)]| {
        let config = through_the_lens(temporal);
        let (_, images) = render_sequence(&gpu, &scene, &config, poses, |f| f == poses.len() - 1);
        periphery_error(&images[0], &reference, &region)
    };
    let bilinear = error(None, &[last]);
    let accumulated = error(Some(TemporalConfig::default()), &turn);
    eprintln!("periphery error through the lens after the turn: bilinear {bilinear:.5}, accumulated {accumulated:.5}");
    assert!(
        accumulated < 0.9 * bilinear,
        "accumulated {accumulated} against bilinear {bilinear}"
    );
    foveate_tests::assert_validation_clean(&gpu);
}
