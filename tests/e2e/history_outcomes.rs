//! What a counting frame says became of each accumulated pixel's history: every pixel
//! accounted for, a reset on the first frame, little dropped while nothing moves, and a
//! walking head's history dropped as off-screen and disoccluded.

use foveate::foveation::{HistoryClip, TemporalConfig};
use foveate::metrics::Region;
use foveate::plan::{CountedStep, RenderConfig};
use foveate::render::{HistoryOutcome, HistoryOutcomes, Renderer, StereoImage};
use foveate::scene::{atrium_scene, walking_pose, Scene};
use foveate::view::Eye;
use foveate_tests::{assert_validation_clean, gpu};
use glam::{Mat4, Vec2};

const SCREEN: u32 = 256;
const RATE_HZ: f32 = 90.0;
/// The gaze, off centre: the fovea's hole and band away from the view's middle.
const GAZE: Vec2 = Vec2::new(0.6, 0.0);

pub(crate) fn config(temporal: TemporalConfig) -> RenderConfig {
    super::temporal::config(SCREEN, Some(temporal))
}

/// Counting frames of `config` at `poses` in order: each frame's history outcomes and its
/// output step's fragments, and the last frame.
pub(crate) fn counted(
    gpu: &foveate::gpu::Gpu,
    scene: &Scene,
    config: &RenderConfig,
    poses: &[Mat4],
) -> (Vec<(HistoryOutcomes, u64)>, StereoImage) {
    let plan = foveate::plan(scene, &config.counting(), gpu.caps()).unwrap();
    let mut renderer = Renderer::new(gpu, &plan, scene).unwrap();
    renderer.set_gaze([GAZE; 2]).unwrap();
    let mut frames = Vec::new();
    for &pose in poses {
        let stats = renderer.render_frame(pose).unwrap();
        let outcomes = stats
            .history
            .expect("an accumulating counting frame counts outcomes");
        frames.push((outcomes, stats.fragments_of(CountedStep::Output)));
    }
    let last = renderer.readback().unwrap();
    drop(renderer);
    assert_validation_clean(gpu);
    (frames, last)
}

fn total(outcomes: &HistoryOutcomes) -> u64 {
    HistoryOutcome::ALL.iter().map(|&o| outcomes.total(o)).sum()
}

/// With the head still, every output pixel has one outcome; the first frame resets every
/// accumulated pixel; later frames reset nothing, lose nothing off-screen or empty, use the
/// history everywhere but the hole, and drop fewer than 1 in 50 pixels as disoccluded (thin
/// edges the jitter moves across a texel: the depth test's residue, measured). Frames that
/// accumulate nothing, and timed frames, count nothing. Mutations: a pixel counted twice (or
/// not at all) fails the first check; a still frame's history tested against its own texel
/// only (`moved = true` in the shader) fails the last.
#[test]
fn a_still_head_counts_every_pixel_and_keeps_its_history() {
    let gpu = gpu();
    let scene = atrium_scene();
    let still = [scene.head; 10];
    let (frames, last) = counted(&gpu, &scene, &config(TemporalConfig::default()), &still);
    for (i, (outcomes, fragments)) in frames.iter().enumerate() {
        assert_eq!(
            total(outcomes),
            *fragments,
            "frame {i}: {outcomes:?} does not add up to the output's {fragments} fragments"
        );
        assert!(
            outcomes.total(HistoryOutcome::Hole) > 0,
            "frame {i}: no hole"
        );
    }
    let accumulated = |o: &HistoryOutcomes| Region::ALL.iter().map(|&r| o.accumulated(r)).sum();
    let (first, _) = &frames[0];
    assert_eq!(
        first.total(HistoryOutcome::Reset),
        accumulated(first),
        "the first frame keeps history: {first:?}"
    );
    for (i, (outcomes, _)) in frames.iter().enumerate().skip(1) {
        let lost: Vec<_> = [
            HistoryOutcome::Reset,
            HistoryOutcome::OffScreen,
            HistoryOutcome::Empty,
        ]
        .into_iter()
        .filter(|&o| outcomes.total(o) > 0)
        .map(|o| (o.name(), outcomes.total(o)))
        .collect();
        assert!(
            lost.is_empty(),
            "frame {i}, head still: history lost: {lost:?}"
        );
        let used = outcomes.total(HistoryOutcome::Kept) + outcomes.total(HistoryOutcome::Clipped);
        let n = accumulated(outcomes);
        assert!(
            used * 10 > n * 9,
            "frame {i}: history used in only {used} of {n}"
        );
        let disoccluded = outcomes.total(HistoryOutcome::Disoccluded);
        assert!(
            disoccluded * 50 < n,
            "frame {i}, head still: {disoccluded} of {n} pixels dropped as disoccluded"
        );
    }

    // Only a counting frame that accumulates counts outcomes, and counting changes no pixel:
    // the timed frames end on the same image.
    let single = super::temporal::config(SCREEN, None).counting();
    let timed = config(TemporalConfig::default());
    for config in [single, timed] {
        let plan = foveate::plan(&scene, &config, gpu.caps()).unwrap();
        assert_eq!(plan.history_outcome_base(), None);
        let mut renderer = Renderer::new(&gpu, &plan, &scene).unwrap();
        renderer.set_gaze([GAZE; 2]).unwrap();
        for &pose in &still {
            let stats = renderer.render_frame(pose).unwrap();
            assert_eq!(stats.history, None);
        }
        if config.count_fragments {
            continue;
        }
        let image = renderer.readback().unwrap();
        assert!(
            Eye::BOTH
                .iter()
                .all(|&e| image.eye(e).data == last.eye(e).data),
            "a counting frame shows another image than the timed frame"
        );
    }
    assert_validation_clean(&gpu);
}

/// A walking head drops history for the reasons it moves: what the turn brings into view is
/// off-screen, and what the step uncovers is disoccluded — over three times as many pixels as
/// the same frames drop with the head still (the jitter's residue at thin edges). Negative
/// control in the test: with the history held to nothing (`HistoryClip::Off`, no depth test)
/// the walk counts no disocclusion. Mutation run: the shader noting a failed depth test as
/// kept fails it.
#[test]
fn a_walking_head_drops_history_for_its_own_reasons() {
    let gpu = gpu();
    let scene = atrium_scene();
    let walk: Vec<Mat4> = (0..12)
        .map(|i| walking_pose(scene.head, i as f32 / RATE_HZ))
        .collect();
    let run = |clip, poses: &[Mat4]| {
        let t = TemporalConfig {
            clip,
            ..Default::default()
        };
        let mut sum = HistoryOutcomes::default();
        let (frames, _) = counted(&gpu, &scene, &config(t), poses);
        frames[1..].iter().for_each(|(o, _)| sum.add(o));
        sum
    };
    let clip = TemporalConfig::default().clip;
    let (walked, still) = (run(clip, &walk), run(clip, &[scene.head; 12]));
    eprintln!("walking: {walked:?}\nstill: {still:?}");
    let disoccluded = |o: &HistoryOutcomes| o.total(HistoryOutcome::Disoccluded);
    assert!(
        disoccluded(&walked) > 3 * disoccluded(&still),
        "walking drops {} pixels as disoccluded over 11 frames, still {}",
        disoccluded(&walked),
        disoccluded(&still)
    );
    assert!(
        walked.total(HistoryOutcome::OffScreen) > 0,
        "a turning head brings nothing new into view: {walked:?}"
    );
    let unheld = run(HistoryClip::Off, &walk);
    assert_eq!(
        disoccluded(&unheld),
        0,
        "negative control: with no depth test the walk counts disocclusion"
    );
}
