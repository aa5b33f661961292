//! The planner's rules for each effect (foveation, masks, MFFR, culling), checked without a GPU.

use super::tests::*;
use super::*;
use crate::scene::default_scene;

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
    // Left out, the views follow the configuration; given, they must be those.
    assert_eq!(planned(&foveated(true)).views, 4);
    assert_eq!(planned(&config(StereoMode::Multiview, 4)).views, 2);
    let e = rejected(
        &RenderConfig {
            views: Some(2),
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
            views: Some(4),
            ..config(StereoMode::Multiview, 4)
        },
        &caps(),
    );
    assert!(e.limit.contains("4 with foveation"), "{e}");
    let bad_ratio = RenderConfig {
        foveation: Some(crate::foveation::FoveationConfig {
            ratio: 1.5,
            ..crate::foveation::FoveationConfig::single_frame()
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

/// The far pass takes its own samples and density; the eye passes keep the frame's.
#[test]
fn the_far_pass_has_samples_and_density_of_its_own() {
    let scene = crate::scene::city_scene();
    let base = with_mffr(crate::mffr::MffrOrder::NearFirst);
    let full = plan(&scene, &base, &caps()).unwrap();
    let custom = RenderConfig {
        mffr: base.mffr.map(|m| crate::mffr::MffrConfig {
            far_msaa: Some(1),
            far_density: 0.5,
            ..m
        }),
        ..base.clone()
    };
    let cheap = plan(&scene, &custom, &caps()).unwrap();
    let far = cheap.far_pass().unwrap();
    assert!(far.resolve.is_none(), "one sample: nothing to resolve");
    assert_eq!(attachment(&cheap, &far.color).samples, 1);
    assert_eq!(attachment(&cheap, &far.depth.unwrap()).samples, 1);
    let eye = &cheap.passes[1];
    assert_eq!(attachment(&cheap, &eye.color).samples, 4);
    let (a, b) = (full.mffr.unwrap(), cheap.mffr.unwrap());
    assert_eq!(
        a.split_m, b.split_m,
        "the split stays at the eyes' disparity"
    );
    for (x, y) in [
        (a.resolution.width, b.resolution.width),
        (a.resolution.height, b.resolution.height),
    ] {
        assert!(y.abs_diff(x.div_ceil(2)) <= 1, "{x} → {y}");
    }
    assert!(cheap
        .to_string()
        .contains("at 1x MSAA and 0.5 the eyes' pixel density"));
    for (msaa, density, field) in [
        (Some(2), 1.0, "mffr far_msaa"),
        (None, 0.2, "mffr far_density"),
        (None, f32::NAN, "mffr far_density"),
    ] {
        let c = RenderConfig {
            mffr: base.mffr.map(|m| crate::mffr::MffrConfig {
                far_msaa: msaa,
                far_density: density,
                ..m
            }),
            ..base.clone()
        };
        let err = plan(&scene, &c, &caps()).unwrap_err();
        assert!(err.to_string().contains(field), "{err}");
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

/// A periphery at its own density and sample count renders each view pair into images of its
/// own, in two passes (auto picks it, one-pass is refused naming the field); the same density
/// as the ratio plans exactly today's shared images. Mutation: sharing the scratch images
/// whatever the sizes fails the first half.
#[test]
fn periphery_density_and_samples_give_each_view_pair_its_images() {
    let split = |density, msaa, layout| RenderConfig {
        foveation: foveated(true)
            .foveation
            .map(|f| crate::foveation::FoveationConfig {
                periphery_density: density,
                periphery_msaa: msaa,
                ..f
            }),
        fovea_layout: layout,
        ..foveated(true)
    };
    let plan = planned(&split(Some(0.25), Some(1), FoveaLayout::Auto));
    let scene: Vec<&PassPlan> = plan
        .passes
        .iter()
        .filter(|p| p.kind == PassKind::Scene)
        .collect();
    assert_eq!(scene.len(), 2, "a periphery and a fovea pass");
    let (periphery, fovea) = (scene[0], scene[1]);
    for u in periphery.uses() {
        let a = attachment(&plan, u);
        assert_eq!(
            (a.width, a.samples),
            (128, 1),
            "{}: 512 x 0.25 at 1x",
            a.name
        );
    }
    assert!(periphery.resolve.is_none(), "1x: no resolve");
    for u in fovea.uses() {
        let a = attachment(&plan, u);
        assert_eq!(
            a.width, 256,
            "{}: the 0.5 window at the screen's density",
            a.name
        );
    }
    assert_eq!(attachment(&plan, &fovea.color).samples, 4);
    let e = plan_err(&split(Some(0.25), None, FoveaLayout::OnePass));
    assert_eq!(e.field, "fovea_layout");
    // Density equal to the ratio: the same plan as without it.
    let coupled = |density| planned(&split(density, None, FoveaLayout::TwoPass)).attachments;
    assert_eq!(coupled(Some(0.5)), coupled(None));
}

/// Temporal accumulation adds no pass: it folds into the output stage, which samples the
/// history and the periphery's depth after its sources and writes the next history as a second
/// attachment; the two history images (32 bits a pixel, the output's size) swap roles
/// every frame, both stored and left ready to be sampled, and barriers treat them as one image.
/// Without it the plan is the same as it always was. Mutations: planning the history
/// unconditionally, leaving the written history's store op to the in-frame rule (DONT_CARE),
/// or deriving barriers per image (the sampled one then waits on nothing), fail it.
#[test]
fn temporal_accumulation_folds_into_the_output_stage_only_when_asked() {
    let with = |temporal: Option<crate::foveation::TemporalConfig>, msaa| RenderConfig {
        foveation: foveated(true)
            .foveation
            .map(|f| crate::foveation::FoveationConfig {
                periphery_density: Some(0.25),
                periphery_msaa: Some(msaa),
                periphery_temporal: temporal,
                ..f
            }),
        fovea_layout: FoveaLayout::Auto,
        ..foveated(true)
    };
    let off = planned(&with(None, 1));
    assert!(off.history.is_none());
    assert!(off.passes.iter().all(|p| p.history.is_none()));
    assert!(off.attachments.iter().all(|a| a.format != Format::Rgb10A2));
    assert!(off.sampled_before_written().is_empty());

    let on = planned(&with(Some(Default::default()), 1));
    let kinds: Vec<PassKind> = on.passes.iter().map(|p| p.kind).collect();
    assert_eq!(kinds, [PassKind::Scene, PassKind::Scene, PassKind::Output]);
    let (periphery, fovea, output) = (&on.passes[0], &on.passes[1], &on.passes[2]);
    let pair = on.history.expect("a history pair");
    let depths = on.depth_history.expect("the periphery's depth as a pair");
    let depth = periphery.depth.unwrap();
    assert_eq!(depths.written, depth.attachment);
    let colour = |p: &PassPlan| p.resolve.unwrap_or(p.color).attachment;
    assert_eq!(
        output.samples,
        [
            colour(periphery),
            colour(fovea),
            pair.read,
            depth.attachment,
            depths.read
        ]
    );
    let written = output
        .history
        .expect("the next history written by the output pass");
    assert_eq!(written.attachment, pair.written);
    let mut kept = vec![pair.read, pair.written, depths.read, depths.written];
    kept.sort();
    assert_eq!(on.sampled_before_written(), kept);
    assert_eq!(
        on.attachments[depths.read].format,
        on.attachments[depth.attachment].format
    );
    assert_eq!(
        (written.store, written.final_layout),
        (StoreOp::Store, Layout::ShaderReadOnly),
        "kept for the next frame, which samples it"
    );
    assert_eq!(
        (depth.store, depth.stencil_store, depth.final_layout),
        (StoreOp::Store, StoreOp::DontCare, Layout::ShaderReadOnly),
        "the depth kept for the samplers, which read no stencil"
    );
    for id in [pair.read, pair.written] {
        let a = &on.attachments[id];
        assert_eq!(
            (a.format, a.width, a.layers, a.transient, a.sampled),
            (Format::Rgb10A2, 512, 2, false, true),
            "{}: the output's pixels",
            a.name
        );
    }
    // The sampled history was written by the frame before, the written one sampled by it.
    let waits = |id, from| {
        output
            .barriers
            .wait
            .iter()
            .any(|b| b.attachment == id && b.from == from)
    };
    assert!(waits(pair.read, Touch::ColourAttachment));
    assert!(waits(pair.written, Touch::Sampled));
    // The frame before's depth was written by its periphery pass; this frame's periphery pass
    // waits on the output pass that sampled its image two frames ago.
    assert!(waits(depths.read, Touch::DepthAttachment));
    assert!(periphery
        .barriers
        .wait
        .iter()
        .any(|b| b.attachment == depth.attachment && b.from == Touch::Sampled));
    assert_eq!(pair.of_frame(1).read, pair.written);

    // Accumulated pixel by pixel, the periphery has no neighbourhood to sharpen or upscale.
    let on = with(Some(Default::default()), 1);
    let sharpened = RenderConfig {
        foveation: on.foveation.map(|f| crate::foveation::FoveationConfig {
            periphery_sharpen: 0.5,
            ..f
        }),
        ..on.clone()
    };
    assert_eq!(plan_err(&sharpened).field, "periphery_sharpen");
    let cubic = RenderConfig {
        foveation: on.foveation.map(|f| crate::foveation::FoveationConfig {
            periphery_filter: crate::foveation::PeripheryFilter::CatmullRom,
            ..f
        }),
        ..on
    };
    assert_eq!(plan_err(&cubic).field, "periphery_filter");
}

/// A device without D32_SFLOAT_S8_UINT depth-stencil attachments (a tile GPU offering
/// D24_UNORM_S8_UINT instead) plans frames without stencil masks, and refuses the HMD mask
/// and foveation's masks naming the field and the format. Mutation: the check gone, the
/// masked plans pass.
#[test]
fn stencil_masks_need_a_depth_stencil_format_the_device_has() {
    let caps = DeviceCaps {
        depth_stencil: false,
        ..caps()
    };
    let scene = default_scene();
    assert!(plan(&scene, &config(StereoMode::Multiview, 4), &caps).is_ok());
    let masked = RenderConfig {
        hmd_mask: true,
        ..config(StereoMode::Multiview, 4)
    };
    for (config, field) in [(masked, "hmd_mask"), (foveated(true), "foveation")] {
        assert!(plan(&scene, &config, &DeviceCaps::generic()).is_ok());
        let error = plan(&scene, &config, &caps).unwrap_err().to_string();
        assert!(
            error.contains(field) && error.contains("D32_SFLOAT_S8_UINT"),
            "{error}"
        );
    }
}
