//! The periphery accumulated at its own texels (`HistoryAt::Periphery`): a pass of its own
//! before the output pass, which composes the accumulated periphery as it would one frame's.

use foveate::foveation::{HistoryAt, TemporalConfig};
use foveate::plan::RenderConfig;
use foveate::scene::atrium_scene;
use foveate_tests::gpu;
use glam::Vec2;

use super::temporal::{
    config, differing_by, gaze_jump, periphery_error, periphery_only, render_sequence, supersampled,
};

const SCREEN: u32 = 128;

fn at_periphery(jitter_cycle: u32) -> RenderConfig {
    at_density(jitter_cycle, None)
}

/// Accumulated in a pass of its own, its history at `density` of the screen's (`None`: the
/// periphery's, 0.5 here).
fn at_density(jitter_cycle: u32, density: Option<f32>) -> RenderConfig {
    config(
        SCREEN,
        Some(TemporalConfig {
            history_at: HistoryAt::Periphery,
            history_density: density,
            jitter_cycle,
            ..Default::default()
        }),
    )
}

/// Without jitter, the first frame accumulated at the periphery's texels (a fresh history: the
/// periphery itself, texel for texel) composes into the first frame accumulated at the output's
/// pixels (a fresh history there: the same periphery upscaled bilinearly; an accumulated
/// periphery samples its textures at the screen's detail, a single frame's at its own, so one
/// frame is not the yardstick): no pixel more than one 8-bit level apart, over the whole
/// image, fovea and band included. Mutations: the accumulation pass given the output's size as
/// its screen (its pixels then read the wrong texels), or a fovea left in it (composed twice),
/// fail it.
#[test]
fn unjittered_the_periphery_history_composes_as_a_fresh_output_history() {
    let gpu = gpu();
    let scene = atrium_scene();
    let pose = [(scene.head, Vec2::new(0.3, -0.2))];
    let at_output = config(
        SCREEN,
        Some(TemporalConfig {
            jitter_cycle: 1,
            ..Default::default()
        }),
    );
    let (plan, fresh) = render_sequence(&gpu, &scene, &at_output, &pose, |_| true);
    let (_, accumulated) = render_sequence(&gpu, &scene, &at_periphery(1), &pose, |_| true);
    let everywhere = [0, 1].map(|_| vec![true; (SCREEN * SCREEN) as usize]);
    let (apart, pixels) = differing_by(&fresh[0], &accumulated[0], &everywhere, 1);
    assert_eq!(
        apart, 0,
        "{apart} of {pixels} pixels differ by more than one level ({:?})",
        plan.eye_resolution
    );
}

/// On a still frame the periphery accumulated at its own texels approaches the supersampled
/// reference as frames go by, and ends closer to it than one frame's periphery; a history at a
/// density between the periphery's and the output's ends closer than the periphery's texels,
/// and the history at the output's pixels, which gathers detail beyond the periphery's
/// density, ends closer still. Negative control in the test: without jitter the history gains
/// nothing from frame to frame. Mutations: the jitter left out of the accumulation pass's block
/// (samples credited to the wrong texels), the history never blended, or the density ignored
/// (the periphery's texels), fail it.
#[test]
fn the_periphery_history_converges_on_a_still_frame() {
    let gpu = gpu();
    let scene = atrium_scene();
    let frames = 24;
    let still = vec![(scene.head, Vec2::ZERO); frames];
    let reference = supersampled(&gpu, &scene, still[0]);
    let error = |config: &RenderConfig| {
        let (plan, images) =
            render_sequence(&gpu, &scene, config, &still, |f| f == 0 || f == frames - 1);
        let region = periphery_only(&plan, Vec2::ZERO);
        images
            .iter()
            .map(|i| periphery_error(i, &reference, &region))
            .collect::<Vec<f64>>()
    };
    let single = error(&config(SCREEN, None));
    let at_output = error(&config(SCREEN, Some(TemporalConfig::default())));
    let accumulated = error(&at_periphery(TemporalConfig::default().jitter_cycle));
    let unjittered = error(&at_periphery(1));
    let between = error(&at_density(
        TemporalConfig::default().jitter_cycle,
        Some(0.75),
    ));
    eprintln!(
        "periphery error (first, last frame): one frame {single:?}, history at the output \
         {at_output:?}, at the periphery {accumulated:?}, at 0.75 {between:?}, unjittered \
         {unjittered:?}"
    );
    assert!(
        between[1] < accumulated[1],
        "a finer history keeps more detail: {between:?} against {accumulated:?}"
    );
    assert!(
        accumulated[1] < 0.95 * accumulated[0],
        "the error falls with frames: {accumulated:?}"
    );
    assert!(
        accumulated[1] < single[1],
        "{accumulated:?} against one frame's {single:?}"
    );
    assert!(
        at_output[1] < accumulated[1],
        "the output's pixels hold more detail: {at_output:?} against {accumulated:?}"
    );
    assert!(
        (unjittered[1] - unjittered[0]).abs() < 0.02 * unjittered[0],
        "negative control: without jitter nothing new arrives: {unjittered:?}"
    );
}

/// After a gaze jump, the periphery accumulated at its own texels starts the old fovea's place
/// from what the fovea showed there (kept in the history over the periphery's hole, at the
/// periphery's texels), not from a fresh frame: its error there lies below a fresh renderer's.
/// No jitter, so only the history differs. Mutation run: the pass keeping nothing over the hole
/// (the fovea's place left out of its block) makes the old hole a fresh frame's, and fails it.
#[test]
fn a_gaze_jump_starts_the_old_fovea_from_what_it_showed_at_the_periphery_texels() {
    let (fovea, jumped, fresh) = gaze_jump(HistoryAt::Periphery);
    eprintln!(
        "at the periphery's texels: the fovea's {fovea}, after the jump {jumped}, fresh {fresh}"
    );
    assert!(
        jumped < fresh - 0.25 * (fresh - fovea),
        "after the jump the old hole's error is {jumped}: the fovea's was {fovea}, a fresh \
         frame's is {fresh}"
    );
}
