//! The planner's rules, checked without a GPU against hand-written device capabilities.

use super::*;
use crate::scene::default_scene;

fn caps() -> DeviceCaps {
    DeviceCaps::generic()
}

fn config(stereo: StereoMode, msaa: u32) -> RenderConfig {
    RenderConfig {
        stereo,
        msaa,
        resolution: Some(Resolution::square(512)),
        ..RenderConfig::default()
    }
}

fn planned(config: &RenderConfig) -> FramePlan {
    plan(&default_scene(), config, &caps()).expect("valid config")
}

fn attachment<'a>(plan: &'a FramePlan, u: &Use) -> &'a AttachmentPlan {
    &plan.attachments[u.attachment]
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
        views: 4,
        foveation: Some(crate::foveation::FoveationConfig::default()),
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

fn rejected(config: &RenderConfig, caps: &DeviceCaps) -> ConfigError {
    plan(&default_scene(), config, caps).expect_err("config must be rejected")
}

#[test]
fn bad_configs_name_field_value_and_limit() {
    let base = config(StereoMode::Multiview, 4);
    let e = rejected(
        &RenderConfig {
            views: 5,
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
            views: 3,
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

#[test]
fn the_plan_prints_its_decisions() {
    let text = planned(&config(StereoMode::Multiview, 4)).to_string();
    for needle in [
        "view mask 0b11",
        "load CLEAR, store DONT_CARE",
        "load DONT_CARE, store STORE",
        "transient",
        "traffic",
    ] {
        assert!(text.contains(needle), "missing `{needle}` in\n{text}");
    }
}

fn foveated(stencil: bool) -> RenderConfig {
    RenderConfig {
        views: 4,
        foveation: Some(crate::foveation::FoveationConfig {
            ratio: 0.5,
            stencil,
            ..Default::default()
        }),
        fovea_layout: FoveaLayout::OnePass,
        ..config(StereoMode::Multiview, 4)
    }
}

#[test]
fn foveation_plans_four_low_resolution_views_in_one_pass() {
    let plan = planned(&foveated(true));
    assert_eq!(plan.passes.len(), 2, "scene pass + composition");
    let pass = &plan.passes[0];
    assert_eq!((pass.kind, pass.view_mask), (PassKind::Scene, 0b1111));
    assert!(pass.has_masks());
    for u in pass.uses() {
        let a = attachment(&plan, u);
        assert!(
            a.layers == 4 && a.width == 256,
            "{}: 4 views at 512 × 0.5",
            a.name
        );
    }
    let depth = attachment(&plan, &pass.depth.unwrap());
    assert_eq!(
        depth.format,
        Format::D32S8,
        "stencil only because the masks need it"
    );
    assert_eq!(
        (pass.depth.unwrap().load, pass.depth.unwrap().store),
        (LoadOp::Clear, StoreOp::DontCare)
    );
    assert!(depth.transient);
}

#[test]
fn composition_samples_the_views_which_are_therefore_stored() {
    let plan = planned(&foveated(true));
    let (scene, composite) = (&plan.passes[0], &plan.passes[1]);
    let views = scene.resolve.expect("MSAA 4 resolves").attachment;
    assert_eq!(
        scene.resolve.unwrap().store,
        StoreOp::Store,
        "sampled later, so stored"
    );
    let views_plan = &plan.attachments[views];
    assert!(views_plan.sampled && !views_plan.transient && !views_plan.read_after_frame);
    assert_eq!(composite.kind, PassKind::Output);
    assert_eq!(composite.samples, vec![views]);
    assert!(composite.depth.is_none() && composite.resolve.is_none());
    let out = attachment(&plan, &composite.color);
    assert_eq!(
        (out.width, out.layers, out.read_after_frame),
        (512, 2, true),
        "full resolution, one layer per eye"
    );
    assert_eq!(
        (composite.color.load, composite.color.store),
        (LoadOp::DontCare, StoreOp::Store)
    );
    assert_eq!(plan.outputs(), vec![composite.color.attachment]);
}

#[test]
fn no_masks_no_stencil() {
    let plan = planned(&foveated(false));
    assert!(!plan.passes[0].has_masks());
    assert!(plan.attachments.iter().all(|a| a.format != Format::D32S8));
}

#[test]
fn foveation_needs_four_views_and_multiview() {
    let e = rejected(
        &RenderConfig {
            views: 2,
            ..foveated(true)
        },
        &caps(),
    );
    assert_eq!((e.field, e.value.as_str()), ("views", "2"));
    let e = rejected(
        &RenderConfig {
            stereo: StereoMode::TwoPass,
            ..foveated(true)
        },
        &caps(),
    );
    assert_eq!(e.field, "stereo");
    let e = rejected(
        &RenderConfig {
            views: 4,
            ..config(StereoMode::Multiview, 4)
        },
        &caps(),
    );
    assert!(e.limit.contains("4 with foveation"), "{e}");
    let bad_ratio = RenderConfig {
        foveation: Some(crate::foveation::FoveationConfig {
            ratio: 1.5,
            ..Default::default()
        }),
        ..foveated(true)
    };
    assert_eq!(rejected(&bad_ratio, &caps()).field, "ratio");
    let probe_without_counter = RenderConfig {
        coverage_probe: true,
        count_fragments: false,
        ..foveated(true)
    };
    assert_eq!(
        rejected(&probe_without_counter, &caps()).field,
        "coverage_probe"
    );
}

fn with_mffr(order: crate::mffr::MffrOrder) -> RenderConfig {
    RenderConfig {
        mffr: Some(crate::mffr::MffrConfig {
            order,
            ..Default::default()
        }),
        ..config(StereoMode::Multiview, 4)
    }
}

#[test]
fn hmd_mask_adds_stencil_and_nothing_else() {
    let off = planned(&config(StereoMode::Multiview, 4));
    let on = planned(&RenderConfig {
        hmd_mask: true,
        ..config(StereoMode::Multiview, 4)
    });
    let depth = |p: &FramePlan| attachment(p, &p.passes[0].depth.unwrap()).format;
    assert_eq!((depth(&off), depth(&on)), (Format::D32, Format::D32S8));
    assert!(on.passes[0].has_masks() && !off.passes[0].has_masks());
    assert_eq!(
        on.passes.len(),
        off.passes.len(),
        "masks are written in the scene pass"
    );
    let lens = on.hmd_mask.expect("lens regions planned");
    // Index has no published hidden-area mesh: the circular fallback hides 1 − π/4.
    assert!((lens[0].hidden_fraction() - (1.0 - std::f64::consts::FRAC_PI_4)).abs() < 1e-9);
    assert!(on.to_string().contains("HMD stencil mask: hides 21.5 %"));
}

#[test]
fn mffr_plans_a_mono_far_pass_the_eye_pass_samples() {
    let scene = crate::scene::city_scene();
    for order in [
        crate::mffr::MffrOrder::NearFirst,
        crate::mffr::MffrOrder::FarFirst,
    ] {
        let plan = plan(&scene, &with_mffr(order), &caps()).unwrap();
        let far = plan.far_pass().expect("far pass planned");
        assert_eq!(
            (far.view_mask, far.draw_set().unwrap()),
            (0, DrawSet::FarField)
        );
        let far_colour = far.resolve.unwrap();
        assert_eq!(far_colour.store, StoreOp::Store, "sampled later, so stored");
        assert!(
            attachment(&plan, &far.color).transient
                && attachment(&plan, &far.depth.unwrap()).transient
        );
        let eye = &plan.passes[1];
        assert_eq!(eye.samples, vec![far_colour.attachment]);
        assert_eq!(
            (eye.far_composite(), eye.draw_set().unwrap()),
            (Some(order), DrawSet::NearField)
        );
        // Only near-first writes stencil.
        let stencil = attachment(&plan, &eye.depth.unwrap()).format == Format::D32S8;
        assert_eq!(stencil, order == crate::mffr::MffrOrder::NearFirst);
        assert!(plan.instance_ids().is_some());
        let m = plan.mffr.unwrap();
        assert_eq!(
            m.resolution,
            Resolution {
                width: attachment(&plan, &far_colour).width,
                height: attachment(&plan, &far_colour).height
            }
        );
    }
}

#[test]
fn a_scene_without_far_content_pays_nothing_for_mffr() {
    // The default scene reaches a few hundred metres; a split past it (or past the far plane)
    // leaves nothing to render far: the plan is exactly the plan without MFFR.
    let scene = default_scene();
    let base = config(StereoMode::Multiview, 4);
    let without = plan(&scene, &base, &caps()).unwrap();
    for split in ["2000m", "0.001px"] {
        let c = RenderConfig {
            mffr: Some(crate::mffr::MffrConfig {
                split: split.parse().unwrap(),
                ..Default::default()
            }),
            far: 3000.0,
            ..base.clone()
        };
        let with = plan(&scene, &c, &caps()).unwrap();
        let plain = RenderConfig {
            far: 3000.0,
            ..base.clone()
        };
        assert_eq!(with, plan(&scene, &plain, &caps()).unwrap(), "{split}");
    }
    let near_only = crate::scene::Scene {
        batches: vec![crate::scene::DrawBatch {
            mesh: 1,
            instances: vec![crate::scene::Instance::new(
                glam::Mat4::IDENTITY,
                glam::Vec3::ONE,
            )],
        }],
        ..default_scene()
    };
    let c = RenderConfig {
        mffr: Some(Default::default()),
        ..base.clone()
    };
    assert_eq!(
        plan(&near_only, &c, &caps()).unwrap(),
        plan(&near_only, &base, &caps()).unwrap()
    );
    assert!(without.far_pass().is_none() && without.instance_ids().is_none());
}

#[test]
fn mffr_needs_an_eye_pass_to_composite_into() {
    let scene = crate::scene::city_scene();
    for stereo in [StereoMode::PerObject, StereoMode::Instanced] {
        let c = RenderConfig {
            stereo,
            ..with_mffr(crate::mffr::MffrOrder::NearFirst)
        };
        assert_eq!(plan(&scene, &c, &caps()).unwrap_err().field, "stereo");
    }
    let two_pass = RenderConfig {
        stereo: StereoMode::TwoPass,
        ..with_mffr(crate::mffr::MffrOrder::NearFirst)
    };
    let p = plan(&scene, &two_pass, &caps()).unwrap();
    assert_eq!(
        p.passes
            .iter()
            .filter(|p| p.far_composite().is_some())
            .count(),
        2
    );
}

#[test]
fn culling_picks_each_pass_its_draw_set_and_adds_only_the_id_buffer() {
    use crate::cull::Strategy;
    use crate::view::Eye;
    let with = |stereo, strategy| RenderConfig {
        culling: Some(CullConfig {
            strategy,
            draw_distance: 320.0,
        }),
        ..config(stereo, 4)
    };
    let sets = |c: &RenderConfig| -> Vec<DrawSet> {
        planned(c)
            .passes
            .iter()
            .filter_map(|p| p.draw_set())
            .collect()
    };
    // The thesis' baseline: each eye's pass culled with its own frustum.
    assert_eq!(
        sets(&with(StereoMode::TwoPass, Strategy::PerEye)),
        [
            DrawSet::VisibleToEye(Eye::Left),
            DrawSet::VisibleToEye(Eye::Right)
        ]
    );
    assert_eq!(
        sets(&with(StereoMode::TwoPass, Strategy::Superfrustum)),
        [DrawSet::Visible, DrawSet::Visible]
    );
    assert_eq!(
        sets(&with(StereoMode::Multiview, Strategy::PerEye)),
        [DrawSet::Visible]
    );
    // Culling changes what is drawn, not the frame's passes or attachments.
    let culled = planned(&with(StereoMode::Multiview, Strategy::Superfrustum));
    let plain = planned(&config(StereoMode::Multiview, 4));
    assert_eq!(culled.attachments, plain.attachments);
    assert_eq!(culled.passes.len(), plain.passes.len());
    let extra: Vec<&str> = culled
        .buffers
        .iter()
        .filter(|b| !plain.buffers.contains(b))
        .map(|b| b.name)
        .collect();
    assert_eq!(extra, ["instance ids"]);
    for bad in [0.0, -1.0, f32::INFINITY, f32::NAN] {
        let c = RenderConfig {
            culling: Some(CullConfig {
                strategy: Strategy::PerEye,
                draw_distance: bad,
            }),
            ..config(StereoMode::Multiview, 4)
        };
        let e = plan(&default_scene(), &c, &caps()).unwrap_err();
        assert_eq!(e.field, "draw distance");
    }
}

/// Layouts and clear values are the plan's: a cleared or overwritten use starts UNDEFINED, the
/// output ends ready for the readback, views sampled by composition end shader-readable,
/// scratch stays in its working layout; colour clears to the sky (the far pass's with alpha 0),
/// depth to the far plane. Mutation: a final layout left at the working one for the output,
/// or a clear colour with the far pass's alpha 1, fails it.
#[test]
fn the_plan_decides_layouts_and_clear_values() {
    let plan = planned(&foveated(true));
    let (scene, composite) = (&plan.passes[0], &plan.passes[1]);
    assert_eq!(
        (scene.color.initial_layout, scene.color.final_layout),
        (Layout::Undefined, Layout::ColorAttachment)
    );
    assert_eq!(scene.color.clear, Some(ClearValue::Color(SKY)));
    let depth = scene.depth.unwrap();
    assert_eq!(depth.final_layout, Layout::DepthStencilAttachment);
    assert_eq!(
        depth.clear,
        Some(ClearValue::DepthStencil {
            depth: 0.0,
            stencil: 0
        })
    );
    let views = scene.resolve.unwrap();
    assert_eq!(
        (views.final_layout, views.clear),
        (Layout::ShaderReadOnly, None)
    );
    assert_eq!(
        (composite.color.initial_layout, composite.color.final_layout),
        (Layout::Undefined, Layout::TransferSrc)
    );
    let mffr = planned(&with_mffr(crate::mffr::MffrOrder::FarFirst));
    let far = mffr.far_pass().unwrap();
    assert_eq!(
        far.color.clear,
        Some(ClearValue::Color([SKY[0], SKY[1], SKY[2], 0.0]))
    );
    assert_eq!(far.resolve.unwrap().final_layout, Layout::ShaderReadOnly);
}

/// Each pass is an ordered list of steps with the stencil state each runs under, decided here:
/// masks first (writing bit 0), the far composite before the scene far-first and after it
/// near-first (the scene then writing bit 1 and the composite testing both bits), the probe
/// last; culled scene steps point at the plan's cull slots. Mutation: the near-first composite
/// recorded before the scene, or a probe testing no stencil, fails it.
#[test]
fn passes_are_ordered_steps_with_their_stencil() {
    use crate::mffr::MffrOrder;
    let kinds = |p: &PassPlan| -> Vec<String> {
        p.steps
            .iter()
            .map(|s| s.to_string().split(' ').next().unwrap().to_string())
            .collect()
    };
    let masked = planned(&RenderConfig {
        hmd_mask: true,
        coverage_probe: true,
        count_fragments: true,
        ..config(StereoMode::Multiview, 1)
    });
    assert_eq!(kinds(&masked.passes[0]), ["mask", "scene", "probe"]);
    let Step::MaskFans { stencil: fans } = masked.passes[0].steps[0] else {
        panic!("mask fans first")
    };
    assert_eq!((fans.pass, fans.write_mask), (StencilOp::Replace, MASK_BIT));
    let probe = masked.passes[0].steps[2].stencil().unwrap();
    assert_eq!(
        (probe.compare, probe.compare_mask),
        (CompareOp::Equal, MASK_BIT)
    );

    let near_first = planned(&with_mffr(MffrOrder::NearFirst));
    let eye = near_first
        .passes
        .iter()
        .find(|p| p.kind == PassKind::Scene)
        .unwrap();
    assert_eq!(kinds(eye), ["scene", "far"]);
    let scene = eye.steps[0].stencil().unwrap();
    assert_eq!(
        (scene.pass, scene.write_mask),
        (StencilOp::Replace, NEAR_BIT)
    );
    let far = eye.steps[1].stencil().unwrap();
    assert_eq!((far.compare_mask, far.reference), (NEAR_BIT, 0));
    let far_first = planned(&with_mffr(MffrOrder::FarFirst));
    let eye = far_first
        .passes
        .iter()
        .find(|p| p.kind == PassKind::Scene)
        .unwrap();
    assert_eq!(kinds(eye), ["far", "scene"]);
    assert_eq!(eye.steps[1].stencil(), None, "far-first needs no stencil");
    // The far pass and the near field are culled into two slots, in pass order.
    assert_eq!(
        near_first.cull_slots,
        [DrawSet::FarField, DrawSet::NearField]
    );
    let slots: Vec<Option<usize>> = near_first
        .passes
        .iter()
        .flat_map(|p| &p.steps)
        .filter_map(|s| match s {
            Step::Scene { cull_slot, .. } => Some(*cull_slot),
            _ => None,
        })
        .collect();
    assert_eq!(slots, [Some(0), Some(1)]);
}

/// Radial density masking: the mask step after the mask fans and before the scene, marking
/// SKIP_BIT; the scene (and probe) skip it on top of the masks; a reconstruction pass samples
/// the masked views, which are therefore stored, and writes the output. Refused with another
/// stereo mode, foveation or MFFR, and with inner ≥ outer. Mutation: the scene not testing
/// SKIP_BIT, or the mask recorded after the scene, fails it.
#[test]
fn radial_density_masks_then_reconstructs() {
    let config = RenderConfig {
        radial_density: Some(RadialDensity::default()),
        hmd_mask: true,
        ..config(StereoMode::Multiview, 4)
    };
    let plan = planned(&config);
    let scene = &plan.passes[0];
    assert!(matches!(scene.steps[0], Step::MaskFans { .. }));
    let Step::RadialMask { stencil: mark } = scene.steps[1] else {
        panic!("{:?}", scene.steps)
    };
    assert_eq!((mark.write_mask, mark.reference), (SKIP_BIT, SKIP_BIT));
    let s = scene.steps[2].stencil().unwrap();
    assert_eq!(
        (s.compare, s.compare_mask & SKIP_BIT, s.reference & SKIP_BIT),
        (CompareOp::Equal, SKIP_BIT, 0),
        "the scene skips the marked quads"
    );
    assert_eq!(
        s.compare_mask & MASK_BIT,
        MASK_BIT,
        "and keeps testing the HMD mask"
    );
    let reconstruct = &plan.passes[1];
    assert_eq!(reconstruct.kind, PassKind::Reconstruct);
    assert_eq!(reconstruct.steps, [Step::Reconstruct]);
    let views = scene.resolve.unwrap();
    assert_eq!(reconstruct.samples, [views.attachment]);
    assert_eq!(views.store, StoreOp::Store);
    assert_eq!(
        attachment(&plan, &scene.depth.unwrap()).format,
        Format::D32S8
    );
    assert_eq!(plan.outputs(), [reconstruct.color.attachment]);

    for bad in [
        RenderConfig {
            stereo: StereoMode::TwoPass,
            ..config.clone()
        },
        RenderConfig {
            radial_density: Some(RadialDensity {
                inner: 0.9,
                outer: 0.5,
            }),
            ..config.clone()
        },
    ] {
        let error = plan_err(&bad);
        assert_eq!(error.field, "radial_density", "{error}");
    }
}

fn plan_err(config: &RenderConfig) -> ConfigError {
    plan(&default_scene(), config, &caps()).unwrap_err()
}

/// The output stage for the lens ends every frame, whatever the stereo mode, sampling the eye
/// images where the scene passes left them; undistorted, a plain stereo frame has no output
/// pass and nothing samples its image. Mutation: a lens plan without the output pass, or an
/// undistorted one with it, fails.
#[test]
fn the_lens_output_pass_ends_every_frame_and_only_when_asked() {
    for stereo in StereoMode::ALL {
        let plain = planned(&config(stereo, 4));
        assert!(plain.passes.iter().all(|p| p.kind != PassKind::Output));
        assert!(plain.lens.is_none());
        let lens = planned(&RenderConfig {
            output: OutputStage::Lens,
            ..config(stereo, 4)
        });
        assert_eq!(lens.passes.len(), plain.passes.len() + 1, "{stereo}");
        let out = lens.passes.last().unwrap();
        let Step::Output(step) = out.steps[0] else {
            panic!("{stereo}: the last pass is the output stage");
        };
        assert!(step.lens);
        let expected = match plain.layout {
            TargetLayout::Layered => OutputSource::Layered,
            TargetLayout::PerEye => OutputSource::PerEye,
            TargetLayout::SideBySide => OutputSource::SideBySide,
        };
        assert_eq!(step.source, expected, "{stereo}");
        assert_eq!(
            out.samples,
            plain.outputs(),
            "{stereo}: samples the eye images"
        );
        assert_eq!(lens.output_layout(), TargetLayout::Layered);
        assert!(lens.lens.is_some());
    }
}

/// The two-pass fovea layout: a 2-view periphery pass and a 2-view fovea pass (views 2 and 3)
/// drawing the fovea's own culled set, into their own images, both sampled by the output
/// pass; one pass with tagged instances otherwise. Fovea culling off, the fovea draws what the
/// periphery draws. Mutation: the fovea pass with first view 0 (it would render the periphery's
/// views) or drawing every instance fails it.
#[test]
fn the_fovea_layouts_plan_their_passes_and_draw_sets() {
    let two = planned(&RenderConfig {
        fovea_layout: FoveaLayout::TwoPass,
        ..foveated(true)
    });
    let kinds: Vec<(PassKind, u32, u32)> = two
        .passes
        .iter()
        .map(|p| (p.kind, p.view_mask, p.first_view))
        .collect();
    assert_eq!(
        kinds,
        [
            (PassKind::Scene, 0b11, 0),
            (PassKind::Scene, 0b11, 2),
            (PassKind::Output, 0b11, 0)
        ]
    );
    assert_eq!(two.passes[0].draw_set(), Some(DrawSet::All));
    assert_eq!(two.passes[1].draw_set(), Some(DrawSet::Fovea));
    assert_eq!(two.cull_slots, [DrawSet::Fovea]);
    let images = [
        two.passes[0].resolve.unwrap().attachment,
        two.passes[1].resolve.unwrap().attachment,
    ];
    assert_ne!(images[0], images[1]);
    assert_eq!(two.passes[2].samples, images);
    assert_eq!(
        two.passes[2].steps[0],
        Step::Output(OutputStep {
            lens: false,
            source: OutputSource::Foveated {
                fovea_layer: 0,
                sharpen: false
            }
        })
    );
    let one = planned(&foveated(true));
    assert_eq!(one.passes[0].draw_set(), Some(DrawSet::FoveaTagged));
    let unculled = planned(&RenderConfig {
        foveation: foveated(true)
            .foveation
            .map(|f| crate::foveation::FoveationConfig {
                cull_fovea: false,
                ..f
            }),
        fovea_layout: FoveaLayout::TwoPass,
        ..foveated(true)
    });
    assert_eq!(unculled.passes[1].draw_set(), Some(DrawSet::All));
    assert!(unculled.cull_slots.is_empty());
}

/// `auto` picks the layout from the driver's quirks and the scene, and says why: two passes
/// where multiview views run one after another or the scene's triangles outnumber a view's
/// pixels, one pass otherwise; as asked when asked.
#[test]
fn auto_fovea_layout_follows_quirks_and_geometry() {
    let auto = RenderConfig {
        fovea_layout: FoveaLayout::Auto,
        ..foveated(true)
    };
    let choice = |scene: &crate::scene::Scene, caps: &DeviceCaps| {
        plan(scene, &auto, caps).unwrap().fovea_layout.unwrap()
    };
    let mut serial = caps();
    serial.quirks.multiview_runs_views_serially = true;
    let c = choice(&default_scene(), &serial);
    assert_eq!(c.layout, FoveaLayout::TwoPass);
    assert!(c.reason.contains("one after another"), "{}", c.reason);
    let small = crate::scene::fill_scene();
    assert!(small.triangle_count() < 256 * 256);
    let c = choice(&small, &caps());
    assert_eq!(c.layout, FoveaLayout::OnePass);
    assert!(c.reason.contains("fragment-bound"), "{}", c.reason);
    let heavy = default_scene();
    assert!(heavy.triangle_count() > 256 * 256);
    assert_eq!(choice(&heavy, &caps()).layout, FoveaLayout::TwoPass);
    let asked = planned(&foveated(true)).fovea_layout.unwrap();
    assert_eq!(
        (asked.layout, asked.reason.as_str()),
        (FoveaLayout::OnePass, "asked for (one-pass)")
    );
}
