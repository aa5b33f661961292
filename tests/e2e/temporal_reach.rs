//! The accumulation's reach (`TemporalConfig::within_deg`): within it the periphery
//! accumulates, beyond it each frame's periphery is shown as it is and keeps no history.

use foveate::foveation::TemporalConfig;
use foveate::metrics::Region;
use foveate::render::HistoryOutcome;
use foveate::scene::atrium_scene;
use foveate_tests::gpu;
use glam::Vec2;

use super::temporal::{config, differing_by, render_sequence};

const SCREEN: u32 = 128;

fn unjittered(within_deg: Option<f32>) -> TemporalConfig {
    TemporalConfig {
        jitter_cycle: 1,
        within_deg,
        ..Default::default()
    }
}

/// Unjittered and still, a reach of 1° (inside the periphery's hole: nothing accumulates)
/// shows on its fourth frame what a fresh history shows on its first — the bilinear periphery
/// under the fovea — with no pixel more than one 8-bit level apart over the whole image. The
/// negative control in the test: accumulating everywhere, the fourth frame has moved away from
/// the first (the nearest texel blended in), which is what the reach ignored would show.
/// Mutations: the beyond-reach pixels shown accumulated (the blend's weight left at 1), or
/// left black (the blend left out), fail it. (The accumulation run beyond the reach and
/// discarded shows the same image: that costs time, not pixels, and only time shows it.)
#[test]
fn beyond_the_reach_each_frame_shows_its_own_periphery() {
    let gpu = gpu();
    let scene = atrium_scene();
    let still = vec![(scene.head, Vec2::new(0.3, -0.2)); 4];
    let everywhere = [0, 1].map(|_| vec![true; (SCREEN * SCREEN) as usize]);
    let last = |f: usize| f == 0 || f == 3;
    let (_, accumulated) = render_sequence(
        &gpu,
        &scene,
        &config(SCREEN, Some(unjittered(None))),
        &still,
        last,
    );
    let (_, reach) = render_sequence(
        &gpu,
        &scene,
        &config(SCREEN, Some(unjittered(Some(1.0)))),
        &still,
        last,
    );
    let (apart, pixels) = differing_by(&accumulated[0], &reach[1], &everywhere, 1);
    assert_eq!(
        apart, 0,
        "{apart} of {pixels} pixels differ by more than one level"
    );
    let (moved, _) = differing_by(&accumulated[0], &accumulated[1], &everywhere, 1);
    assert!(
        moved > pixels / 200,
        "negative control: accumulating everywhere, only {moved} of {pixels} pixels changed"
    );
}

/// A counting frame counts the pixels beyond the reach as their own outcome: with a reach of
/// 20° some of the periphery accumulates (its history kept) and some lies beyond; with none,
/// nothing lies beyond. Every pixel still has one outcome. Mutation: the outcome left
/// unnoted (beyond-reach pixels counted as kept) fails it.
#[test]
fn a_counting_frame_counts_the_pixels_beyond_the_reach() {
    let gpu = gpu();
    let scene = atrium_scene();
    let poses = vec![scene.head; 3];
    let count = |within_deg| {
        let config = super::history_outcomes::config(TemporalConfig {
            within_deg,
            ..Default::default()
        });
        super::history_outcomes::counted(&gpu, &scene, &config, &poses).0
    };
    let (reach, fragments) = count(Some(20.0))[2];
    let beyond = reach.get(HistoryOutcome::Beyond, Region::Periphery);
    let kept = reach.get(HistoryOutcome::Kept, Region::Periphery);
    assert!(beyond > 0 && kept > 0, "beyond {beyond}, kept {kept}");
    let total: u64 = HistoryOutcome::ALL.iter().map(|&o| reach.total(o)).sum();
    assert_eq!(total, fragments, "one outcome per output fragment");
    let (everywhere, _) = count(None)[2];
    assert_eq!(everywhere.total(HistoryOutcome::Beyond), 0);
}
