//! What of each frame's periphery enters the history (`NewSample`): the nearest texel alone, or
//! the 3×3 texels around the pixel, each weighted by its distance from the pixel's centre, where
//! the point moved.

use foveate::foveation::{ClipNeighbourhood, FoveationConfig, NewSample, TemporalConfig};
use foveate::metrics::temporal::Flicker;
use foveate::metrics::{EyePixels, Region};
use foveate::plan::RenderConfig;
use foveate::render::StereoImage;
use foveate::scene::atrium_scene;
use glam::{Mat4, Vec2};

use crate::temporal::{config, render_sequence, turning};

const SCREEN: u32 = 128;

/// The mean flicker in the periphery of `frames` against `reference` (4× stereo's own change
/// is not flicker: `metrics::temporal`), the regions those of `plan` with the gaze ahead.
fn periphery_flicker(
    plan: &foveate::plan::FramePlan,
    reference: &[StereoImage],
    frames: &[StereoImage],
) -> f64 {
    let pixels = EyePixels::both(plan, Vec2::ZERO, plan.foveation.as_ref());
    let mut flicker = Flicker::default();
    for (r, t) in reference.iter().zip(frames) {
        flicker.push(r.eyes(), t.eyes(), &pixels).unwrap();
    }
    let periphery = Region::ALL.iter().position(|&r| r == Region::Periphery);
    flicker.summary().regions[periphery.unwrap()].unwrap().mean
}

/// Along half a second of a head turning 20°/s, with the periphery at the screen's density
/// (where the walk's measurements found the largest difference), the weighted new sample
/// flickers less in the periphery than the nearest texel alone: as the texels move past a
/// pixel, which one is nearest switches and its colour enters at once. Mutation runs: the
/// pixel's centre taken with the jitter's sign flipped (weighted 0.00698 against the nearest's
/// 0.00506) fails it, and so does the constant never set (0.00506 both).
#[test]
fn the_weighted_new_sample_flickers_less_along_a_turn() {
    let gpu = foveate_tests::gpu();
    let scene = atrium_scene();
    let turn = turning(&scene);
    let with = |new_sample: NewSample| {
        let base = config(SCREEN, None);
        let config = RenderConfig {
            foveation: Some(FoveationConfig {
                periphery_density: Some(1.0),
                periphery_temporal: Some(TemporalConfig {
                    new_sample,
                    ..TemporalConfig::default()
                }),
                ..base.foveation.unwrap()
            }),
            ..base
        };
        render_sequence(&gpu, &scene, &config, &turn, |_| true)
    };
    let stereo = RenderConfig {
        foveation: None,
        msaa: 4,
        ..config(SCREEN, None)
    };
    let (_, reference) = render_sequence(&gpu, &scene, &stereo, &turn, |_| true);
    let (plan, weighted) = with(NewSample::Weighted);
    let (_, nearest) = with(NewSample::Nearest);
    let (w, n) = (
        periphery_flicker(&plan, &reference, &weighted),
        periphery_flicker(&plan, &reference, &nearest),
    );
    eprintln!("periphery flicker along the turn: weighted {w:.5}, nearest {n:.5}");
    assert!(w < 0.9 * n, "weighted {w} against the nearest's {n}");
}

/// The weighted new sample is taken only where the head's motion moved the point, from the reads
/// the clip's box makes there: with the head still, weighted and nearest give the same image to
/// the bit. And where the box takes the cross of five texels, the weighted sample reads the 3×3
/// but the box still counts the cross alone: along a turn, the cross and the square differ.
/// Mutation runs: the weighted sample taken everywhere fails the first half; the box counting
/// every texel the sample read, the second.
#[test]
fn the_weighted_new_sample_changes_only_what_moved() {
    let gpu = foveate_tests::gpu();
    let scene = atrium_scene();
    let with = |new_sample, neighbourhood, poses: &[(Mat4, Vec2)]| {
        let t = TemporalConfig {
            new_sample,
            neighbourhood,
            ..TemporalConfig::default()
        };
        render_sequence(&gpu, &scene, &config(SCREEN, Some(t)), poses, |f| {
            f == poses.len() - 1
        })
        .1
    };
    let still = vec![(scene.head, Vec2::ZERO); 12];
    let (weighted, nearest) = (
        with(NewSample::Weighted, ClipNeighbourhood::Square, &still),
        with(NewSample::Nearest, ClipNeighbourhood::Square, &still),
    );
    assert!(
        weighted[0] == nearest[0],
        "with the head still, the weighted new sample changes the image"
    );
    let turn = turning(&scene);
    let (square, cross) = (
        with(NewSample::Weighted, ClipNeighbourhood::Square, &turn),
        with(NewSample::Weighted, ClipNeighbourhood::Cross, &turn),
    );
    assert!(
        square[0] != cross[0],
        "turning, with the weighted new sample, the cross's box is the square's"
    );
}
