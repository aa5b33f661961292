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

/// `config` with the periphery accumulated, its history held by `clip`.
fn clipped(clip: HistoryClip) -> RenderConfig {
    config(Some(TemporalConfig {
        clip,
        ..Default::default()
    }))
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
/// clip is what holds it). `HistoryClip::Moved` clips where the head moved and where the
/// walker, an instance the renderer moves, lies or lay: with the head still, only that mark
/// holds it. Mutation runs: the shader's clip removed while its disocclusion test stays (the
/// kept history unclipped) fails it, 606 of 2,280 pixels trailing against 737 unclipped; with
/// the scene pass not marking the walker, `moved` trails as `depth` does (606); with the
/// history's mark ignored (only the walker's pixels now are clipped, not those it left), 425.
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
        let accumulated = walked(&gpu, &scene, walker, &clipped(clip), last);
        ghost(&accumulated, &end, &uncovered)
    };
    // Without clipping the trail is plain (negative control): the test can see one.
    let (unclipped, region) = run(HistoryClip::Off);
    assert!(
        unclipped * 10 > region,
        "negative control: without clipping only {unclipped} of {region} pixels trail"
    );
    // So does the depth test alone.
    let (trail, _) = run(HistoryClip::DepthOnly);
    eprintln!("clip depth: {trail} of {region} pixels trail");
    assert!(
        trail * 10 > region,
        "the depth test alone holds the walker: only {trail} of {region} pixels trail"
    );
    // Clipped, what remains hugs the walker's trailing edge (the periphery's neighbourhood
    // there still holds its red): a small fraction of the unclipped trail.
    for clip in [
        HistoryClip::Range,
        HistoryClip::Variance { sigmas: 1.0 },
        HistoryClip::Moved,
    ] {
        let (ghosts, _) = run(clip);
        eprintln!("clip {clip}: {ghosts} of {region} pixels trail; unclipped {unclipped}");
        assert!(
            ghosts * 4 < unclipped,
            "clip {clip}: {ghosts} of the {region} uncovered pixels keep a red trail \
             (unclipped: {unclipped})"
        );
    }
}

/// `config`'s frame `after` frames after the walker, standing where it starts (never moved,
/// so never marked as moving), was taken out of the scene `before` frames in, read back.
fn removed(
    gpu: &foveate::gpu::Gpu,
    scene: &Scene,
    walker: Walker,
    config: &RenderConfig,
    (before, after): (usize, usize),
) -> StereoImage {
    let plan = foveate::plan(scene, config, gpu.caps()).unwrap();
    let mut renderer = Renderer::new(gpu, &plan, scene).unwrap();
    renderer.set_gaze([GAZE; 2]).unwrap();
    for frame in 0..before + after {
        if frame == before {
            renderer.remove_instance(walker.instance).unwrap();
        }
        renderer.render_frame(scene.head).unwrap();
    }
    let image = renderer.readback().unwrap();
    drop(renderer);
    assert_validation_clean(gpu);
    image
}

/// An instance that never moved, taken out, leaves no trail either with the clip only where
/// something moved (`HistoryClip::Moved`): no pixel of it is marked, so the frame after the
/// removal clips everywhere. Two frames after it, what is redder than a frame without the
/// walker where the walker stood stays within the range clip's count. Negative control in the
/// test: the depth test alone keeps most of it (666 of 1,056 pixels when written: the test
/// cannot tell it from what lies just behind). Mutation run: the frame after a removal not
/// clipping everywhere fails it (`moved` 666, as the depth test alone).
#[test]
fn a_removed_instance_leaves_no_trail() {
    let gpu = gpu();
    let mut scene = atrium_scene();
    let walker = Walker::add(&mut scene, 4.0);
    let frames = (24, 2);
    let single = config(None);
    let with = removed(&gpu, &scene, walker, &single, (frames.0 + frames.1, 0));
    let without = removed(&gpu, &scene, walker, &single, frames);
    let stood = differ(&with, &without, 24);
    let run = |clip| {
        let accumulated = removed(&gpu, &scene, walker, &clipped(clip), frames);
        ghost(&accumulated, &without, &stood)
    };
    let (depth_only, region) = run(HistoryClip::DepthOnly);
    let (range, _) = run(HistoryClip::Range);
    let (moved, _) = run(HistoryClip::Moved);
    eprintln!(
        "of {region} pixels the walker stood on: depth {depth_only}, range {range}, moved {moved}"
    );
    assert!(region > 200, "the walker covers only {region} pixels");
    assert!(
        depth_only > 2 * range.max(10),
        "negative control: the depth test alone leaves only {depth_only} pixels (range: {range})"
    );
    assert!(
        moved <= range + range / 4,
        "moved leaves {moved} of {region} pixels redder where the walker stood; range {range}"
    );
}
