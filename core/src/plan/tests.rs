//! The planner's rules, checked without a GPU against hand-written device capabilities.

use super::*;
use crate::scene::default_scene;

pub(super) fn caps() -> DeviceCaps {
    DeviceCaps::generic()
}

pub(super) fn config(stereo: StereoMode, msaa: u32) -> RenderConfig {
    RenderConfig {
        stereo,
        msaa,
        resolution: Some(Resolution::square(512)),
        ..RenderConfig::default()
    }
}

pub(super) fn planned(config: &RenderConfig) -> FramePlan {
    plan(&default_scene(), config, &caps()).expect("valid config")
}

pub(super) fn attachment<'a>(plan: &'a FramePlan, u: &Use) -> &'a AttachmentPlan {
    &plan.attachments[u.attachment]
}

pub(super) fn foveated(stencil: bool) -> RenderConfig {
    RenderConfig {
        foveation: Some(crate::foveation::FoveationConfig {
            ratio: 0.5,
            stencil,
            ..crate::foveation::FoveationConfig::single_frame()
        }),
        fovea_layout: FoveaLayout::OnePass,
        ..config(StereoMode::Multiview, 4)
    }
}

/// MFFR drawn `order` first, its far image at the eyes' density (exact up to the disparity
/// bound; the default resamples it at 0.8).
pub(super) fn with_mffr(order: crate::mffr::MffrOrder) -> RenderConfig {
    RenderConfig {
        mffr: Some(crate::mffr::MffrConfig {
            order,
            far_density: 1.0,
            ..Default::default()
        }),
        ..config(StereoMode::Multiview, 4)
    }
}

pub(super) fn plan_err(config: &RenderConfig) -> ConfigError {
    plan(&default_scene(), config, &caps()).unwrap_err()
}

#[test]
fn msaa_scene_pass_is_transient_and_resolved_in_the_pass() {
    for stereo in StereoMode::ALL {
        let plan = planned(&config(stereo, 4));
        for pass in &plan.passes {
            for u in [&pass.color, &pass.depth.expect("scene passes have depth")] {
                let a = attachment(&plan, u);
                assert_eq!(a.samples, 4, "{stereo}: {}", a.name);
                assert_eq!(
                    (u.load, u.store),
                    (LoadOp::Clear, StoreOp::DontCare),
                    "{stereo}: {}",
                    a.name
                );
                assert!(a.transient, "{stereo}: {} must be transient", a.name);
            }
            let resolve = pass.resolve.expect("MSAA resolves inside the pass");
            let target = attachment(&plan, &resolve);
            assert_eq!((target.samples, target.role), (1, AttachmentRole::Resolve));
            assert_eq!(
                (resolve.load, resolve.store),
                (LoadOp::DontCare, StoreOp::Store),
                "{stereo}"
            );
            assert!(!target.transient && target.read_after_frame);
        }
    }
}

#[test]
fn without_msaa_there_is_no_multisampled_image_and_no_resolve() {
    for stereo in StereoMode::ALL {
        let plan = planned(&config(stereo, 1));
        assert!(plan.attachments.iter().all(|a| a.samples == 1), "{stereo}");
        assert!(
            plan.attachments
                .iter()
                .all(|a| a.role != AttachmentRole::Resolve),
            "{stereo}"
        );
        for pass in &plan.passes {
            assert!(pass.resolve.is_none());
            assert_eq!(
                (pass.color.load, pass.color.store),
                (LoadOp::Clear, StoreOp::Store)
            );
            assert_eq!(
                (pass.depth.unwrap().load, pass.depth.unwrap().store),
                (LoadOp::Clear, StoreOp::DontCare)
            );
        }
        assert_eq!(
            plan.attachments.len(),
            2,
            "{stereo}: colour (a layer per eye for two-pass) and depth only"
        );
    }
}

#[test]
fn depth_has_no_stencil_while_no_effect_needs_it() {
    for stereo in StereoMode::ALL {
        let plan = planned(&config(stereo, 4));
        assert!(
            plan.attachments.iter().all(|a| a.format != Format::D32S8),
            "{stereo}"
        );
    }
}

#[test]
fn stereo_modes_lay_out_their_targets() {
    let multiview = planned(&config(StereoMode::Multiview, 4));
    assert_eq!(multiview.passes.len(), 1);
    assert_eq!(multiview.passes[0].view_mask, 0b11);
    assert!(multiview
        .attachments
        .iter()
        .all(|a| a.layers == 2 && a.width == 512));

    // Two-pass: scratch MSAA images (one layer) shared by both passes; each eye resolves into
    // its own layer of the stereo image — or, on a driver whose in-pass resolve ignores the
    // base layer, into its own image.
    let two_pass = planned(&config(StereoMode::TwoPass, 4));
    assert_eq!(two_pass.layout, TargetLayout::Layered);
    assert_eq!(two_pass.passes.len(), 2);
    assert!(two_pass.passes.iter().all(|p| p.view_mask == 0));
    let outputs = two_pass.outputs();
    assert_eq!(outputs.len(), 1);
    assert_eq!(two_pass.attachments[outputs[0]].layers, 2);
    for (eye, pass) in two_pass.passes.iter().enumerate() {
        let resolve = pass.resolve.unwrap();
        assert_eq!(
            (resolve.attachment, resolve.base_layer, resolve.layer_count),
            (outputs[0], eye as u32, 1)
        );
        assert_eq!(resolve.store, StoreOp::Store, "each eye's layer is stored");
        assert_eq!(attachment(&two_pass, &pass.color).layers, 1);
        assert_eq!(pass.color.attachment, two_pass.passes[0].color.attachment);
    }
    let mut quirky = caps();
    quirky.quirks.layered_resolve_ignores_base_layer = true;
    let per_eye = plan(&default_scene(), &config(StereoMode::TwoPass, 4), &quirky).unwrap();
    assert_eq!(per_eye.layout, TargetLayout::PerEye);
    assert!(per_eye.attachments.iter().all(|a| a.layers == 1));
    let outputs = per_eye.outputs();
    assert_eq!(outputs.len(), 2);
    for (eye, pass) in per_eye.passes.iter().enumerate() {
        let resolve = pass.resolve.unwrap();
        assert_eq!(resolve.attachment, outputs[eye]);
        assert_eq!(resolve.store, StoreOp::Store, "each eye's image is stored");
    }

    for stereo in [StereoMode::PerObject, StereoMode::Instanced] {
        let plan = planned(&config(stereo, 4));
        assert_eq!(plan.layout, TargetLayout::SideBySide);
        assert!(
            plan.attachments
                .iter()
                .all(|a| a.layers == 1 && a.width == 1024),
            "{stereo}"
        );
    }
}

#[test]
fn draw_calls_follow_the_submission_strategy() {
    let scene = default_scene();
    let meshes = scene.draws().count() as u64;
    let calls = |s| planned(&config(s, 1)).draw_calls_estimate;
    assert_eq!(calls(StereoMode::Multiview), meshes);
    assert_eq!(calls(StereoMode::Instanced), meshes);
    assert_eq!(calls(StereoMode::TwoPass), 2 * meshes);
    assert_eq!(
        calls(StereoMode::PerObject),
        2 * scene.instance_count() as u64
    );
}

/// Timed frames carry no counters: the default plan has its timestamps and no counting
/// resource; the counting twin has the counter and no timestamps. Mutation: counting on by
/// default, or `counting()` keeping timestamps, fails it.
#[test]
fn timed_plans_carry_no_counters_and_counting_plans_no_timestamps() {
    let off = RenderConfig {
        timestamps: false,
        ..config(StereoMode::Multiview, 1)
    };
    let plan = planned(&off);
    assert!(plan.buffers.is_empty() && plan.counted.is_empty());
    assert_eq!(plan.timestamp_queries, 0);
    let timed = planned(&config(StereoMode::Multiview, 1));
    assert!(!timed.count_fragments() && timed.counted.is_empty() && timed.buffers.is_empty());
    assert_eq!(timed.timestamp_queries, 2);
    let counting = planned(&config(StereoMode::Multiview, 1).counting());
    assert_eq!(counting.buffers.len(), 1);
    assert_eq!(counting.timestamp_queries, 0);
    assert_eq!(
        counting.counted,
        vec![CountedSlot {
            pass: 0,
            step: CountedStep::Scene
        }]
    );
}

/// Where the driver writes a query after a multiview pass into one slot per view, every query
/// pool gets the most views of any pass, less one, spare slots past its end (the frame's 4-view
/// foveated pass: 3); elsewhere none, and none when no query is made. Mutation: spare slots
/// counted from the last pass's views only (the output pass has two), fails it.
#[test]
fn query_pools_get_spare_slots_where_queries_span_views() {
    let mut quirky = caps();
    quirky.quirks.queries_after_multiview_span_views = true;
    let foveated = RenderConfig {
        foveation: Some(crate::foveation::FoveationConfig::single_frame()),
        fovea_layout: FoveaLayout::OnePass,
        ..config(StereoMode::Multiview, 1)
    };
    for (config, most_views) in [(config(StereoMode::Multiview, 1), 2), (foveated, 4)] {
        let timed = plan(&default_scene(), &config, &quirky).expect("valid config");
        assert_eq!(timed.query_spare_slots, most_views - 1);
        assert_eq!(
            timed.timestamp_pool_slots(),
            timed.timestamp_queries + most_views - 1
        );
        assert_eq!(timed.statistics_pool_slots(), 0, "no statistics: no pool");
        let counting = plan(&default_scene(), &config.counting(), &quirky).expect("valid");
        assert_eq!(
            counting.statistics_pool_slots(),
            counting.statistics_queries + most_views - 1
        );
        let untimed = RenderConfig {
            timestamps: false,
            ..config.clone()
        };
        let untimed = plan(&default_scene(), &untimed, &quirky).expect("valid config");
        assert_eq!(untimed.query_spare_slots, 0);
        let elsewhere = plan(&default_scene(), &config, &caps()).expect("valid config");
        assert_eq!(elsewhere.query_spare_slots, 0);
        assert_eq!(
            elsewhere.timestamp_pool_slots(),
            elsewhere.timestamp_queries
        );
    }
}

/// Every step that shades fragments has its own counter slots, in recording order: the mask
/// fans, the far composite (before the scene far-first, after it near-first), the scene, the
/// composition. Mutation: a step left out of `counted_steps` (as the composite and masks once
/// were) fails it.
#[test]
fn counting_covers_every_step_that_shades() {
    use crate::mffr::MffrOrder;
    let steps = |config: RenderConfig| {
        let plan = planned(&config.counting());
        let counted: Vec<(&str, CountedStep)> = plan
            .counted
            .iter()
            .map(|c| (plan.passes[c.pass].name, c.step))
            .collect();
        let bases: Vec<u32> = plan
            .counted
            .iter()
            .map(|c| plan.counter_base(c.pass, c.step).unwrap())
            .collect();
        let slots = COUNTER_SLOTS_PER_STEP;
        assert_eq!(
            bases,
            (0..counted.len() as u32)
                .map(|i| i * slots)
                .collect::<Vec<_>>()
        );
        assert_eq!(
            plan.fragment_counter().unwrap().bytes,
            4 * (slots as u64) * counted.len() as u64
        );
        counted
    };
    assert_eq!(
        steps(foveated(true)),
        vec![
            ("scene (foveated multiview)", CountedStep::Mask),
            ("scene (foveated multiview)", CountedStep::Scene),
            ("output (fovea over periphery)", CountedStep::Output),
        ]
    );
    for (order, expected) in [
        (
            MffrOrder::FarFirst,
            [CountedStep::FarComposite, CountedStep::Scene],
        ),
        (
            MffrOrder::NearFirst,
            [CountedStep::Scene, CountedStep::FarComposite],
        ),
    ] {
        let counted = steps(with_mffr(order));
        assert_eq!(counted[0], ("far field (mono)", CountedStep::Scene));
        assert_eq!(
            counted[1..].iter().map(|c| c.1).collect::<Vec<_>>(),
            expected
        );
    }
}

#[test]
fn bytes_and_traffic_add_up() {
    let plan = planned(&config(StereoMode::Multiview, 4));
    let eye = 512 * 512;
    // MSAA colour + depth: 2 layers × 4 samples × 4 bytes each, all transient.
    assert_eq!(plan.transient_bytes(), 2 * (eye * 2 * 4 * 4));
    assert_eq!(plan.resident_bytes(), eye * 2 * 4);
    // Only the resolve target is stored, then read back once.
    assert_eq!(plan.external_traffic_bytes(), 2 * eye * 2 * 4);
}

#[test]
fn guard_band_only_where_the_driver_needs_it() {
    let plan = planned(&config(StereoMode::Multiview, 4));
    assert!(plan.passes.iter().all(|p| p.guard_band == 1));
    let mut quirky = caps();
    quirky.quirks.multiview_clipping_drops_views = true;
    let plan = super::plan(&default_scene(), &config(StereoMode::Multiview, 4), &quirky).unwrap();
    assert_eq!(plan.passes[0].guard_band, 8);
    // Only multiview passes need it.
    let plan = super::plan(&default_scene(), &config(StereoMode::TwoPass, 4), &quirky).unwrap();
    assert!(plan.passes.iter().all(|p| p.guard_band == 1));
    // A grown viewport the device cannot take is not used.
    quirky.max_viewport_dimension = 1024;
    let plan = super::plan(&default_scene(), &config(StereoMode::Multiview, 4), &quirky).unwrap();
    assert_eq!(plan.passes[0].guard_band, 2);
}

pub(super) fn rejected(config: &RenderConfig, caps: &DeviceCaps) -> ConfigError {
    plan(&default_scene(), config, caps).expect_err("config must be rejected")
}

#[test]
fn bad_configs_name_field_value_and_limit() {
    let base = config(StereoMode::Multiview, 4);
    let e = rejected(
        &RenderConfig {
            views: Some(5),
            ..base.clone()
        },
        &caps(),
    );
    assert_eq!((e.field, e.value.as_str()), ("views", "5"));
    assert!(e.limit.contains("at most 4"), "{e}");

    let e = rejected(
        &RenderConfig {
            msaa: 8,
            ..base.clone()
        },
        &caps(),
    );
    assert_eq!((e.field, e.value.as_str()), ("msaa", "8"));
    assert!(e.limit.contains("1, 4"), "{e}");

    let e = rejected(
        &RenderConfig {
            resolution: Some(Resolution {
                width: 0,
                height: 512,
            }),
            ..base.clone()
        },
        &caps(),
    );
    assert_eq!((e.field, e.value.as_str()), ("resolution", "0x512"));
    assert!(e.limit.contains("1..=8192"), "{e}");

    let e = rejected(
        &RenderConfig {
            ipd_m: Some(f32::NAN),
            ..base.clone()
        },
        &caps(),
    );
    assert_eq!((e.field, e.value.as_str()), ("ipd", "NaN"));

    let e = rejected(
        &RenderConfig {
            hmd: "pimax".into(),
            ..base.clone()
        },
        &caps(),
    );
    assert_eq!((e.field, e.value.as_str()), ("hmd", "pimax"));
    assert!(
        e.limit.contains("index") && e.limit.contains("quest2"),
        "{e}"
    );

    let e = rejected(
        &RenderConfig {
            near: 0.0,
            ..base.clone()
        },
        &caps(),
    );
    assert_eq!(e.field, "near");
    let e = rejected(
        &RenderConfig {
            far: 0.01,
            ..base.clone()
        },
        &caps(),
    );
    assert_eq!(e.field, "far");
    let e = rejected(
        &RenderConfig {
            cant_deg: Some(f32::INFINITY),
            ..base.clone()
        },
        &caps(),
    );
    assert_eq!(e.field, "cant");
    let bad_fov = crate::view::FovTangents {
        left: -1.0,
        right: 0.5,
        up: 1.0,
        down: 1.0,
    };
    let e = rejected(
        &RenderConfig {
            fov: Some(bad_fov),
            ..base.clone()
        },
        &caps(),
    );
    assert_eq!(e.field, "fov");
    // Side-by-side modes need twice the width.
    let wide = RenderConfig {
        resolution: Some(Resolution::square(5000)),
        stereo: StereoMode::Instanced,
        ..base.clone()
    };
    assert_eq!(rejected(&wide, &caps()).field, "resolution");
    assert!(plan(
        &default_scene(),
        &RenderConfig {
            stereo: StereoMode::Multiview,
            ..wide
        },
        &caps()
    )
    .is_ok());
}

#[test]
fn device_limits_are_the_limits() {
    let base = config(StereoMode::Multiview, 4);
    let mut two_views = caps();
    two_views.max_multiview_views = 2;
    let e = rejected(
        &RenderConfig {
            views: Some(3),
            ..base.clone()
        },
        &two_views,
    );
    assert!(e.limit.contains("at most 2"), "{e}");

    let mut no_multiview = caps();
    no_multiview.max_multiview_views = 0;
    let e = rejected(&base, &no_multiview);
    assert_eq!((e.field, e.value.as_str()), ("views", "2"));

    let mut no_clip = caps();
    no_clip.shader_clip_distance = false;
    let e = rejected(
        &RenderConfig {
            stereo: StereoMode::Instanced,
            ..base.clone()
        },
        &no_clip,
    );
    assert_eq!(e.field, "stereo");
    assert!(e.limit.contains("shaderClipDistance"));

    let mut no_msaa = caps();
    no_msaa.framebuffer_sample_counts = 1;
    assert_eq!(rejected(&base, &no_msaa).field, "msaa");
}

#[test]
fn parsing_resolution_and_mode() {
    assert_eq!(
        "1024".parse::<Resolution>().unwrap(),
        Resolution::square(1024)
    );
    assert_eq!(
        "1440x1600".parse::<Resolution>().unwrap(),
        Resolution {
            width: 1440,
            height: 1600
        }
    );
    assert_eq!("abc".parse::<Resolution>().unwrap_err().field, "resolution");
    assert_eq!(
        "two-pass".parse::<StereoMode>().unwrap(),
        StereoMode::TwoPass
    );
    assert_eq!("stereo".parse::<StereoMode>().unwrap_err().field, "stereo");
}

/// An output handed in per frame (an OpenXR swapchain's image) ends every frame where a
/// runtime's compositor takes it: stored, in `COLOR_ATTACHMENT_OPTIMAL`; otherwise the frame
/// ends ready for readback. Mutation: leaving `TransferSrc` hands the runtime the wrong layout.
#[test]
fn an_external_output_ends_as_a_colour_attachment() {
    for config in [
        config(StereoMode::Multiview, 4),
        config(StereoMode::TwoPass, 1),
        foveated(true),
        with_mffr(crate::mffr::MffrOrder::NearFirst),
    ] {
        let own = planned(&config);
        let external = planned(&RenderConfig {
            external_output: true,
            ..config.clone()
        });
        // Every use of the output (the two-pass layout writes a layer per pass).
        let output_uses = |plan: &FramePlan| -> Vec<Use> {
            let output = plan.outputs()[0];
            plan.passes
                .iter()
                .flat_map(|p| p.uses().copied())
                .filter(|u| u.attachment == output)
                .collect()
        };
        for u in output_uses(&own) {
            assert_eq!(u.final_layout, Layout::TransferSrc);
        }
        for u in output_uses(&external) {
            assert_eq!(
                (u.final_layout, u.store),
                (Layout::ColorAttachment, StoreOp::Store)
            );
            assert_eq!(external.attachments[u.attachment].layers, 2);
        }
        assert_eq!(own.passes.len(), external.passes.len(), "the same passes");
    }
}

/// A swapchain image holds both eyes as two layers: both eyes side by side in one image are
/// refused with the field named.
#[test]
fn an_external_output_must_be_layered() {
    for stereo in [StereoMode::PerObject, StereoMode::Instanced] {
        let err = plan_err(&RenderConfig {
            external_output: true,
            ..config(stereo, 4)
        });
        assert_eq!(err.field, "external_output", "{stereo:?}: {err}");
    }
}

#[test]
fn the_hidden_area_mesh_needs_the_hmd_mask() {
    let err = plan_err(&RenderConfig {
        hidden_area_mesh: true,
        ..config(StereoMode::Multiview, 4)
    });
    assert_eq!(err.field, "hidden_area_mesh");
    let plan = planned(&RenderConfig {
        hidden_area_mesh: true,
        hmd_mask: true,
        ..config(StereoMode::Multiview, 4)
    });
    assert!(
        plan.to_string().contains("the runtime's hidden-area mesh"),
        "{plan}"
    );
}
