//! Each step's pipeline as its builder states it, checked without a GPU against the compiled
//! shaders: a stage gets every constant its SPIR-V declares (none falls back to its GLSL default)
//! and a pipeline states no constant neither stage declares (which would split the cache).

use std::collections::BTreeSet;

use super::*;
use crate::cull::Strategy;
use crate::foveation::FoveationConfig;
use crate::mffr::{MffrConfig, MffrOrder, MffrVariant};
use crate::scene::{atrium_scene, default_scene, Scene, Shading};

fn base(stereo: StereoMode) -> RenderConfig {
    RenderConfig {
        stereo,
        msaa: 4,
        resolution: Some(Resolution::square(256)),
        ..RenderConfig::default()
    }
}

/// Configurations reaching every step kind, submission and shader variant.
fn configurations() -> Vec<(Scene, RenderConfig)> {
    let foveated = |layout, count_fragments| RenderConfig {
        foveation: Some(FoveationConfig {
            ratio: 0.5,
            stencil: true,
            periphery_sharpen: 0.5,
            ..FoveationConfig::single_frame()
        }),
        fovea_layout: layout,
        culling: Some(CullConfig {
            strategy: Strategy::Superfrustum,
            draw_distance: 320.0,
        }),
        count_fragments,
        ..base(StereoMode::Multiview)
    };
    let mffr = |stereo, order, variant, count_fragments| RenderConfig {
        mffr: Some(MffrConfig {
            order,
            variant,
            ..Default::default()
        }),
        hmd_mask: true,
        count_fragments,
        ..base(stereo)
    };
    let mut configs: Vec<RenderConfig> = StereoMode::ALL
        .into_iter()
        .flat_map(|stereo| {
            let far_field = matches!(stereo, StereoMode::Multiview | StereoMode::TwoPass);
            [
                Some(base(stereo)),
                Some(RenderConfig {
                    hmd_mask: true,
                    coverage_probe: stereo == StereoMode::Multiview,
                    output: OutputStage::Lens,
                    count_fragments: true,
                    ..base(stereo)
                }),
                far_field.then(|| mffr(stereo, MffrOrder::FarFirst, MffrVariant::Centre, false)),
                far_field
                    .then(|| mffr(stereo, MffrOrder::NearFirst, MffrVariant::DepthShift, true)),
            ]
        })
        .flatten()
        .collect();
    configs.extend([
        foveated(FoveaLayout::OnePass, false),
        foveated(FoveaLayout::OnePass, true),
        foveated(FoveaLayout::TwoPass, true),
        // Temporal accumulation, in both layouts, timed and counted.
        RenderConfig {
            msaa: 1,
            foveation: foveated(FoveaLayout::OnePass, false)
                .foveation
                .map(|f| FoveationConfig {
                    periphery_temporal: Some(Default::default()),
                    periphery_sharpen: 0.0,
                    ..f
                }),
            ..foveated(FoveaLayout::OnePass, false)
        },
        RenderConfig {
            msaa: 1,
            foveation: foveated(FoveaLayout::TwoPass, true)
                .foveation
                .map(|f| FoveationConfig {
                    periphery_temporal: Some(Default::default()),
                    // Nothing to sharpen: the accumulated periphery is at the output's pixels.
                    periphery_sharpen: 0.0,
                    ..f
                }),
            ..foveated(FoveaLayout::TwoPass, true)
        },
        RenderConfig {
            radial_density: Some(RadialDensity::default()),
            count_fragments: true,
            ..base(StereoMode::Multiview)
        },
        RenderConfig {
            radial_density: Some(RadialDensity::default()),
            ..base(StereoMode::Multiview)
        },
    ]);
    let lit = atrium_scene().with_shading(Shading::Lit);
    let mut out: Vec<(Scene, RenderConfig)> =
        configs.into_iter().map(|c| (default_scene(), c)).collect();
    out.push((lit.clone(), base(StereoMode::Multiview)));
    let mut masked = lit.clone();
    masked.materials[0].alpha_cutoff = Some(0.5);
    out.push((masked.clone(), base(StereoMode::Multiview)));
    out.push((
        masked,
        RenderConfig {
            count_fragments: true,
            ..base(StereoMode::Multiview)
        },
    ));
    out.push((
        lit,
        RenderConfig {
            count_fragments: true,
            ..base(StereoMode::TwoPass)
        },
    ));
    out
}

fn ids(desc: &PipelineDesc) -> BTreeSet<u32> {
    desc.constants.iter().map(|c| c.0.id()).collect()
}

/// Mutation: a builder forgetting `FIRST_VIEW` (the two-pass fovea pass would draw the periphery
/// views), the scene step stating `FOVEA_TAGS` for the plain vertex shader, or `constant()`
/// no longer filtering by the shaders fails it.
#[test]
fn every_stage_gets_exactly_the_constants_its_shader_declares() {
    let mut stages = BTreeSet::new();
    let mut plans: Vec<FramePlan> = (configurations().into_iter())
        .map(|(scene, config)| {
            plan(&scene, &config, &DeviceCaps::generic())
                .unwrap_or_else(|e| panic!("{config:?}: {e}"))
        })
        .collect();
    // An engine's frame on a driver whose resolve lands in layer 0: its copy passes.
    let mut quirky = DeviceCaps::generic();
    quirky.quirks.multiview_clipping_drops_views = true;
    quirky.quirks.layered_resolve_ignores_base_layer = true;
    for count_fragments in [false, true] {
        let config = RenderConfig {
            foveation: Some(crate::foveation::FoveationConfig::default()),
            count_fragments,
            ..RenderConfig::default()
        };
        plans.push(crate::plan::plan_for_engine(&config, &quirky).unwrap());
    }
    for plan in &plans {
        for pass in &plan.passes {
            assert_eq!(pass.pipelines.len(), pass.steps.len(), "{}", pass.name);
            for (step, desc) in pass.steps.iter().zip(&pass.pipelines) {
                let stated = ids(desc);
                let declared: BTreeSet<u32> = [desc.vertex, desc.fragment]
                    .iter()
                    .flat_map(|s| s.spec_ids())
                    .collect();
                assert_eq!(
                    stated, declared,
                    "{} / {step}: {desc} states other constants than its shaders declare",
                    pass.name
                );
                assert_eq!(desc.stencil, step.stencil(), "{step}");
                stages.insert((desc.vertex.name, desc.fragment.name));
            }
        }
    }
    // Every shader variant is reached by some configuration above.
    let reached: BTreeSet<&str> = stages.iter().flat_map(|&(v, f)| [v, f]).collect();
    for shader in crate::shaders::ALL {
        assert!(
            reached.contains(shader.name),
            "no configuration uses {shader:?}"
        );
    }
}

/// The descriptions differ wherever the pipelines must: two passes of a two-pass fovea layout
/// differ only in their first view, and a counting frame's scene step in its shader and slot.
/// Mutation: `FIRST_VIEW` dropped from the scene step fails it.
#[test]
fn pipelines_that_differ_in_a_constant_are_not_the_same_value() {
    let config = RenderConfig {
        foveation: Some(FoveationConfig {
            ratio: 0.5,
            ..FoveationConfig::single_frame()
        }),
        fovea_layout: FoveaLayout::TwoPass,
        ..base(StereoMode::Multiview)
    };
    let planned = plan(&default_scene(), &config, &DeviceCaps::generic()).unwrap();
    let scene_pipeline = |p: &PassPlan| {
        p.steps
            .iter()
            .position(|s| matches!(s, Step::Scene { .. }))
            .map(|i| p.pipelines[i].clone())
    };
    let scenes: Vec<PipelineDesc> = planned.passes.iter().filter_map(scene_pipeline).collect();
    assert_eq!(scenes.len(), 2, "periphery and fovea passes");
    assert_ne!(scenes[0], scenes[1]);
    let first_view = |d: &PipelineDesc| {
        d.constants
            .iter()
            .find(|c| c.0 == Constant::FirstView)
            .map(|c| c.1)
    };
    assert_eq!(
        (first_view(&scenes[0]), first_view(&scenes[1])),
        (Some(0), Some(2))
    );
    let text = planned.to_string();
    assert!(
        text.contains("scene pipeline: scene_indirect.vert + scene.frag; scene vertices"),
        "{text}"
    );
    assert!(text.contains("FIRST_VIEW=2"), "{text}");
}

/// The value `constant` takes in the frame's output step, if it is set.
fn output_step_constant(planned: &FramePlan, constant: Constant) -> Option<u32> {
    let output = planned.passes.last().unwrap();
    let step = output
        .steps
        .iter()
        .position(|s| matches!(s, Step::Output(_)))
        .expect("the output step");
    output.pipelines[step]
        .constants
        .iter()
        .find(|c| c.0 == constant)
        .map(|c| c.1)
}

/// The history's Catmull-Rom read, the clip's cross neighbourhood and the weighted new sample
/// are compiled into the accumulating output stage only when the configuration asks for them:
/// the default frame's pipeline has none. Mutations: the Catmull-Rom constant set from the clip
/// instead of the filter fails it; so does the cross's or the weighted sample's constant never
/// set.
#[test]
fn the_history_filter_is_a_constant_of_the_output_stage() {
    use crate::foveation::{ClipNeighbourhood, HistoryFilter, NewSample, TemporalConfig};
    let output_constant = |temporal: TemporalConfig, constant: Constant| {
        let config = RenderConfig {
            msaa: 1,
            foveation: Some(FoveationConfig {
                ratio: 0.35,
                periphery_density: Some(0.5),
                periphery_msaa: Some(1),
                periphery_temporal: Some(temporal),
                ..FoveationConfig::single_frame()
            }),
            ..base(StereoMode::Multiview)
        };
        let planned = plan(&atrium_scene(), &config, &DeviceCaps::generic()).unwrap();
        output_step_constant(&planned, constant)
    };
    let default = TemporalConfig::default();
    let sharp = TemporalConfig {
        filter: HistoryFilter::CatmullRom,
        ..default
    };
    let cross = TemporalConfig {
        neighbourhood: ClipNeighbourhood::Cross,
        ..default
    };
    assert_ne!(
        output_constant(default, Constant::HistoryCatmullRom),
        Some(1)
    );
    assert_eq!(output_constant(sharp, Constant::HistoryCatmullRom), Some(1));
    assert_ne!(
        output_constant(sharp, Constant::CrossNeighbourhood),
        Some(1)
    );
    assert_ne!(
        output_constant(default, Constant::CrossNeighbourhood),
        Some(1)
    );
    assert_eq!(
        output_constant(cross, Constant::CrossNeighbourhood),
        Some(1)
    );
    let weighted = TemporalConfig {
        new_sample: NewSample::Weighted,
        ..default
    };
    assert_ne!(
        output_constant(default, Constant::WeightedNewSample),
        Some(1)
    );
    assert_eq!(
        output_constant(weighted, Constant::WeightedNewSample),
        Some(1)
    );
}

/// The accumulating output stage looks for instances that move exactly where the scene passes
/// mark them (a plan whose instances move, clipped where things moved); elsewhere it builds the
/// clip's box only where it clips. Mutation: the flag never set on the output stage fails it
/// (and the walker's test then finds a trail).
#[test]
fn the_output_stage_looks_for_moving_instances_where_the_scene_marks_them() {
    use crate::foveation::{HistoryClip, TemporalConfig};
    for (moving, clip) in [
        (false, HistoryClip::Moved),
        (true, HistoryClip::Moved),
        (true, HistoryClip::DepthOnly),
    ] {
        let config = RenderConfig {
            msaa: 1,
            moving_instances: moving,
            foveation: Some(FoveationConfig {
                ratio: 0.35,
                periphery_density: Some(0.5),
                periphery_msaa: Some(1),
                periphery_temporal: Some(TemporalConfig {
                    clip,
                    ..Default::default()
                }),
                ..FoveationConfig::single_frame()
            }),
            ..base(StereoMode::Multiview)
        };
        let planned = plan(&atrium_scene(), &config, &DeviceCaps::generic()).unwrap();
        let marked = moving && clip == HistoryClip::Moved;
        let scene_marks = planned.passes[0]
            .pipelines
            .iter()
            .any(|p| p.constants.contains(&(Constant::MarkMoving, 1)));
        assert_eq!(scene_marks, marked, "{moving} {clip}");
        assert_eq!(
            output_step_constant(&planned, Constant::MarkMoving) == Some(1),
            marked,
            "{moving} {clip}"
        );
    }
}

/// A lit scene's loop over its point lights is bounded by a constant: its scene pipelines state
/// the scene's count, and a flat scene's state none. (Bounded by a uniform buffer's value, the
/// loop made lavapipe 22.3 compile the shader anew at every bind and leak it.) Mutation: the
/// constant left unset states nothing and shades no point light.
#[test]
fn lit_scene_pipelines_state_the_scenes_point_lights() {
    let lit = atrium_scene();
    let flat = atrium_scene().with_shading(Shading::Flat);
    assert!(!lit.lights.is_empty());
    for (scene, lights) in [(&lit, lit.lights.len() as u32), (&flat, 0)] {
        let plan = plan(scene, &base(StereoMode::Multiview), &DeviceCaps::generic()).unwrap();
        assert_eq!(plan.point_lights, lights);
        let stated: Vec<u32> = plan
            .passes
            .iter()
            .flat_map(|p| &p.pipelines)
            .filter_map(|d| d.constants.iter().find(|c| c.0 == Constant::PointLights))
            .map(|c| c.1)
            .collect();
        match lights {
            0 => assert!(stated.is_empty(), "{stated:?}"),
            n => assert!(
                !stated.is_empty() && stated.iter().all(|&v| v == n),
                "{stated:?}"
            ),
        }
    }
}
