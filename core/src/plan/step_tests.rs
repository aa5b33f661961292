//! Layouts, clear values, step order and the output pass as planned, checked without a GPU.

use super::tests::*;
use super::*;
use crate::scene::default_scene;

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
    let Step::MaskFans { stencil: fans, .. } = masked.passes[0].steps[0] else {
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
            },
            temporal: false,
            periphery_only: false,
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
