//! Temporal accumulation meeting a surface that moves on its own: a walker crossing the
//! periphery leaves no trail behind it.

use foveate::foveation::{HistoryClip, TemporalConfig};
use foveate::plan::RenderConfig;
use foveate::render::{Renderer, StereoImage};
use foveate::scene::{atrium_scene, Scene, Walker};
use foveate::view::Eye;
use foveate_tests::{assert_validation_clean, gpu};
use glam::Vec2;

const SCREEN: u32 = 256;
/// The gaze, far to the right: the walker (starting 2 m left of 4 m ahead) is in the periphery.
const GAZE: Vec2 = Vec2::new(0.6, 0.0);
const FRAMES: usize = 45;
const RATE_HZ: f32 = 90.0;

fn config(temporal: Option<TemporalConfig>) -> RenderConfig {
    RenderConfig {
        moving_instances: true,
        ..super::temporal::config(SCREEN, temporal)
    }
}

/// `config`'s frame after the walker walked from its start for `frames` frames (the head and
/// gaze still), read back.
fn walked(
    gpu: &foveate::gpu::Gpu,
    scene: &Scene,
    walker: Walker,
    config: &RenderConfig,
    frames: usize,
) -> StereoImage {
    let plan = foveate::plan(scene, config, gpu.caps()).unwrap();
    let mut renderer = Renderer::new(gpu, &plan, scene).unwrap();
    renderer.set_gaze([GAZE; 2]).unwrap();
    for frame in 0..frames {
        let t = frame as f32 / RATE_HZ;
        renderer
            .move_instance(walker.instance, walker.model(t))
            .unwrap();
        renderer.render_frame(scene.head).unwrap();
    }
    let image = renderer.readback().unwrap();
    drop(renderer);
    assert_validation_clean(gpu);
    image
}

/// Pixels where two images differ by more than `levels` in some channel, per eye.
fn differ(a: &StereoImage, b: &StereoImage, levels: u8) -> [Vec<bool>; 2] {
    Eye::BOTH.map(|e| {
        let (x, y) = (a.eye(e), b.eye(e));
        (0..x.height)
            .flat_map(|py| (0..x.width).map(move |px| (px, py)))
            .map(|(px, py)| {
                let (p, q) = (x.pixel(px, py), y.pixel(px, py));
                (0..3).any(|c| p[c].abs_diff(q[c]) > levels)
            })
            .collect()
    })
}

/// Where `image` is redder than `fresh` (red over green) by more than 24 levels, within
/// `region`: a ghost of the red walker. Returns (ghost pixels, region pixels).
fn ghost(image: &StereoImage, fresh: &StereoImage, region: &[Vec<bool>; 2]) -> (usize, usize) {
    let (mut ghost, mut n) = (0, 0);
    for e in Eye::BOTH {
        let (a, b) = (image.eye(e), fresh.eye(e));
        for py in 0..a.height {
            for px in 0..a.width {
                if !region[e.index()][(py * a.width + px) as usize] {
                    continue;
                }
                n += 1;
                let redness = |p: [u8; 4]| p[0] as i32 - p[1] as i32;
                ghost += (redness(a.pixel(px, py)) - redness(b.pixel(px, py)) > 24) as usize;
            }
        }
    }
    (ghost, n)
}

/// A walker crossing the periphery leaves no trail: where it stood in the earlier frames and
/// no longer stands, the accumulated frame is redder than a frame without accumulation in
/// less than a quarter of the pixels it is without clipping. Negative control in the test:
/// with the history not clipped to the periphery's neighbourhood (`HistoryClip::Off`) the
/// trail covers over a tenth of the region and the test sees it, and so it does with the depth
/// test alone (`HistoryClip::DepthOnly`: the walker uncovers too little a frame for it; the
/// clip is what holds it), or with the clip only where the head moved (`HistoryClip::Moved`). Mutation run: the shader's clip removed while its disocclusion test
/// stays (the kept history unclipped) fails it, 248 of 2,280 pixels trailing against 357
/// unclipped.
#[test]
fn a_walker_leaves_no_trail() {
    let gpu = gpu();
    let mut scene = atrium_scene();
    let walker = Walker::add(&mut scene, 4.0);
    let last = FRAMES;
    // Without accumulation (nothing to trail): the walker where it ends, and where it started.
    let single = config(None);
    let end = walked(&gpu, &scene, walker, &single, last);
    let start = walked(&gpu, &scene, walker, &single, 1);
    // The trail's region: the walker's pixels at the start that show the background at the end
    // (the walker at the start differs from the end frame, and is gone by the end).
    let uncovered = differ(&start, &end, 24);
    let n: usize = uncovered.iter().flatten().filter(|&&u| u).count();
    assert!(
        n > 200,
        "the walker uncovers only {n} pixels: it does not move"
    );

    let run = |clip| {
        let t = TemporalConfig {
            clip,
            ..Default::default()
        };
        let accumulated = walked(&gpu, &scene, walker, &config(Some(t)), last);
        ghost(&accumulated, &end, &uncovered)
    };
    // Without clipping the trail is plain (negative control): the test can see one.
    let (unclipped, region) = run(HistoryClip::Off);
    assert!(
        unclipped * 10 > region,
        "negative control: without clipping only {unclipped} of {region} pixels trail"
    );
    // So does the clip only where the head moved the point: here the head is still.
    for clip in [HistoryClip::DepthOnly, HistoryClip::Moved] {
        let (trail, _) = run(clip);
        eprintln!("clip {clip}: {trail} of {region} pixels trail");
        assert!(
            trail * 10 > region,
            "clip {clip} holds the walker: only {trail} of {region} pixels trail"
        );
    }
    // Clipped, what remains hugs the walker's trailing edge (the periphery's neighbourhood
    // there still holds its red): a small fraction of the unclipped trail.
    for clip in [HistoryClip::Range, HistoryClip::Variance { sigmas: 1.0 }] {
        let (ghosts, _) = run(clip);
        eprintln!("clip {clip}: {ghosts} of {region} pixels trail; unclipped {unclipped}");
        assert!(
            ghosts * 4 < unclipped,
            "clip {clip}: {ghosts} of the {region} uncovered pixels keep a red trail \
             (unclipped: {unclipped})"
        );
    }
}
