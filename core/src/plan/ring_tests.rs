//! The parafoveal ring as planned: six views, the fovea's pass rendering the ring's two.

use super::pipeline::Constant;
use super::tests::*;
use super::*;
use crate::foveation::FoveationConfig;

fn ringed(layout: FoveaLayout) -> RenderConfig {
    RenderConfig {
        foveation: foveated(true).foveation.map(|f| FoveationConfig {
            ratio: 0.25,
            periphery_density: Some(0.25),
            ring_ratio: Some(0.5),
            ..f
        }),
        fovea_layout: layout,
        ..foveated(true)
    }
}

/// A ring makes six views: the periphery's pass keeps its two, the fovea's pass renders four
/// (its own two, then the ring's) into images of four layers, draws what the periphery draws
/// (the ring is wider than the fovea's frusta), and the output composes the ring
/// (`RING`); the plan says so. Mutations: the fovea's pass left at two views or two layers, its
/// draws culled to the fovea's frusta, or the constant left off, fail it.
#[test]
fn the_fovea_pass_renders_the_ring() {
    let plan = planned(&ringed(FoveaLayout::Auto));
    assert_eq!(plan.views, 6);
    let scenes: Vec<&PassPlan> = plan
        .passes
        .iter()
        .filter(|p| p.kind == PassKind::Scene)
        .collect();
    let masks: Vec<(u32, u32)> = scenes.iter().map(|p| (p.view_mask, p.first_view)).collect();
    assert_eq!(masks, [(0b11, 0), (0b1111, 2)]);
    let fovea_target = scenes[1].resolve.expect("multisampled").attachment;
    assert_eq!(plan.attachments[fovea_target].layers, 4);
    let layout = plan.fovea_layout.as_ref().expect("foveated");
    assert_eq!(layout.layout, FoveaLayout::TwoPass);
    assert!(
        !layout.cull,
        "the fovea's pass draws what the ring sees too"
    );
    let composes = plan
        .passes
        .iter()
        .flat_map(|p| &p.pipelines)
        .any(|p| p.constants.contains(&(Constant::Ring, 1)));
    assert!(composes);
    assert!(
        plan.to_string().contains(
            "  parafoveal ring: a window 0.5 of the field wide at 0.50 of the screen's density"
        ),
        "{plan}"
    );

    let two = planned(&RenderConfig {
        fovea_layout: FoveaLayout::Auto,
        ..foveated(true)
    });
    assert_eq!(two.views, 4);
    assert!(!two.to_string().contains("parafoveal ring"));
}

/// The ring is refused, naming `ring_ratio`, where the fovea's pass is not its own (the
/// one-pass layout), with MFFR, with the prefilter and with an engine's draws. Mutation: any
/// refusal dropped fails it.
#[test]
fn the_ring_is_refused_where_the_fovea_pass_cannot_hold_it() {
    let refused = |result: Result<FramePlan, ConfigError>| {
        assert_eq!(result.expect_err("refused").field, "ring_ratio");
    };
    let scene = crate::scene::default_scene();
    refused(plan(&scene, &ringed(FoveaLayout::OnePass), &caps()));
    refused(plan(
        &scene,
        &RenderConfig {
            mffr: Some(crate::mffr::MffrConfig::default()),
            ..ringed(FoveaLayout::Auto)
        },
        &caps(),
    ));
    let prefiltered = ringed(FoveaLayout::Auto);
    refused(plan(
        &crate::scene::atrium_scene(),
        &RenderConfig {
            foveation: prefiltered.foveation.map(|f| FoveationConfig {
                periphery_prefilter: true,
                ..f
            }),
            ..prefiltered.clone()
        },
        &caps(),
    ));
    refused(plan_for_engine(&ringed(FoveaLayout::Auto), &caps()));
}
