//! The library's default foveation, and what the plan says of how the periphery is made.

use super::tests::*;
use super::*;
use crate::foveation::{FoveationConfig, HistoryAt, TemporalConfig, RECOMMENDED_PERIPHERY_DENSITY};

/// The default is the verdict's configuration: the periphery accumulated at the recommended
/// density, its history at the output's pixels, beside a fovea at the frame's samples; single
/// frames plan no history and the periphery at the fovea's ratio. Mutation: the default back to
/// single frames, or its density left to the ratio, fails it.
#[test]
fn the_default_accumulates_the_periphery_at_the_recommended_density() {
    let with = |f: FoveationConfig| RenderConfig {
        foveation: Some(f),
        fovea_layout: FoveaLayout::Auto,
        ..foveated(true)
    };
    let default = planned(&with(FoveationConfig::default()));
    let g = default.foveation.expect("foveated");
    let t = g.temporal.expect("the default accumulates");
    assert_eq!(t, TemporalConfig::default());
    assert_eq!(t.history_at, HistoryAt::Output);
    assert!(default.history.is_some(), "a history pair");
    let density = default.periphery_density().expect("a periphery") as f32;
    assert!(
        (density - RECOMMENDED_PERIPHERY_DENSITY).abs() < 0.01,
        "{density}"
    );
    assert_eq!(g.periphery_samples(4), 1, "the accumulated periphery is 1x");

    let single = planned(&with(FoveationConfig::single_frame()));
    let g = single.foveation.expect("foveated");
    assert!(g.temporal.is_none() && single.history.is_none());
    assert_eq!(
        g.periphery_view, g.fovea_view,
        "Arm's four views of one size"
    );
}

/// The plan says how the periphery is made and why: one frame or accumulated (the library's
/// default, and why it is), at its own density, not the fovea views'. Mutations: the two arms
/// swapped, the density read off the fovea views (0.5 here), or every accumulation called the
/// default, fail it.
#[test]
fn the_plan_says_why_the_periphery_is_made_as_it_is() {
    let with = |temporal: Option<TemporalConfig>| RenderConfig {
        foveation: foveated(true).foveation.map(|f| FoveationConfig {
            periphery_density: Some(0.25),
            periphery_temporal: temporal,
            ..f
        }),
        fovea_layout: FoveaLayout::Auto,
        ..foveated(true)
    };
    let one = planned(&with(None)).to_string();
    assert!(
        one.contains("  periphery: one frame at 0.25 of the screen's density"),
        "{one}"
    );
    assert!(one.contains("the library's default accumulates"), "{one}");
    let accumulated = planned(&with(Some(Default::default()))).to_string();
    let line = "  periphery: accumulated over jittered frames at 0.25 of the screen's density";
    assert!(accumulated.contains(line), "{accumulated}");
    assert!(
        !accumulated.contains("this is the library's default"),
        "{accumulated}"
    );
    // The library's default says that it is, and why.
    let default = RenderConfig {
        foveation: Some(FoveationConfig::default()),
        ..with(None)
    };
    let default = planned(&default).to_string();
    let line = "  periphery: accumulated over jittered frames at 0.60 of the screen's density";
    assert!(default.contains(line), "{default}");
    assert!(
        default.contains("this is the library's default: the cheapest configuration measured"),
        "{default}"
    );
    let stereo = planned(&config(StereoMode::Multiview, 4)).to_string();
    assert!(!stereo.contains("  periphery:"), "{stereo}");
}

/// The periphery's specular prefilter: a lit scene's single-frame periphery gets it, its scene
/// pipelines carrying the constant and the plan saying so; without it no pipeline carries the
/// constant. A flat scene, an accumulated periphery and an engine's draws refuse it, each
/// naming the field. Mutations: the constant set regardless of the flag, or any refusal
/// dropped, fail it.
#[test]
fn only_a_lit_single_frame_periphery_is_prefiltered() {
    use crate::scene::{atrium_scene, default_scene};
    let with = |prefilter: bool, temporal: Option<TemporalConfig>| RenderConfig {
        foveation: foveated(true).foveation.map(|f| FoveationConfig {
            periphery_density: Some(0.25),
            periphery_temporal: temporal,
            periphery_prefilter: prefilter,
            ..f
        }),
        fovea_layout: FoveaLayout::Auto,
        ..foveated(true)
    };
    let carries = |plan: &FramePlan| {
        plan.passes.iter().flat_map(|p| &p.pipelines).any(|p| {
            p.constants
                .contains(&(super::pipeline::Constant::PeripheryPrefilter, 1))
        })
    };
    let lit = atrium_scene();
    let prefiltered = plan(&lit, &with(true, None), &caps()).expect("a lit single frame");
    assert!(carries(&prefiltered));
    let line = "one frame at 0.25 of the screen's density, its highlights prefiltered";
    assert!(prefiltered.to_string().contains(line), "{prefiltered}");
    let plain = plan(&lit, &with(false, None), &caps()).expect("valid");
    assert!(!carries(&plain) && !plain.to_string().contains("prefiltered"));

    let refused = |result: Result<FramePlan, ConfigError>| {
        let e = result.expect_err("refused");
        assert_eq!(e.field, "periphery_prefilter", "{e}");
    };
    refused(plan(&default_scene(), &with(true, None), &caps()));
    refused(plan(&lit, &with(true, Some(Default::default())), &caps()));
    refused(plan_for_engine(&with(true, None), &caps()));
}
