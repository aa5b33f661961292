use ash::vk;
use foveate::gpu::{Gpu, Image, ImageDesc};
use foveate::plan::{RenderConfig, Resolution, StereoMode};
use foveate::scene::{ground_quad, DrawBatch, Instance, Scene};
use foveate::view::look_at_head;
use foveate_tests::{assert_validation_clean, gpu, render_plan};
use glam::{Mat4, Quat, Vec3};

/// A wall in front of the viewer, wider than the view: every triangle crosses the viewport's
/// left or right edge, so the driver has to clip all of them.
fn wide_wall() -> Scene {
    let model = Mat4::from_scale_rotation_translation(
        Vec3::new(13.0, 1.0, 2.0),
        Quat::from_rotation_x(std::f32::consts::FRAC_PI_2),
        Vec3::new(0.0, 1.6, -5.0),
    );
    Scene {
        meshes: vec![ground_quad()],
        batches: vec![DrawBatch {
            mesh: 0,
            instances: vec![Instance::new(model, Vec3::ONE)],
        }],
        head: look_at_head(Vec3::new(0.0, 1.6, 0.0), Vec3::new(0.0, 1.3, -10.0)),
        light_dir: -Vec3::Y,
        materials: Vec::new(),
        lights: Vec::new(),
        reach: None,
    }
}

/// `multiview_clipping_drops_views` is measured, not assumed: without the guard band a driver
/// with the quirk loses view 1's clipped triangles (they land in layer 0), with it multiview
/// matches two-pass exactly; a driver without the quirk gets no guard band and loses nothing.
#[test]
fn lavapipe_multiview_clipping_quirk_is_real() {
    let gpu = gpu();
    let scene = wide_wall();
    let config = |stereo| RenderConfig {
        stereo,
        msaa: 1,
        resolution: Some(Resolution::square(64)),
        count_fragments: true,
        ..RenderConfig::default()
    };
    let two_pass = foveate::plan(&scene, &config(StereoMode::TwoPass), gpu.caps()).unwrap();
    let (_, reference) = render_plan(&gpu, &scene, &two_pass, 1);
    let planned = foveate::plan(&scene, &config(StereoMode::Multiview), gpu.caps()).unwrap();
    let (_, as_planned) = render_plan(&gpu, &scene, &planned, 1);
    assert_eq!(
        as_planned.fragments, reference.fragments,
        "planned multiview matches two-pass"
    );

    let quirk = gpu.caps().quirks.multiview_clipping_drops_views;
    assert_eq!(planned.passes[0].guard_band > 1, quirk);
    let mut unguarded = planned.clone();
    unguarded.passes[0].guard_band = 1;
    let (_, without_guard) = render_plan(&gpu, &scene, &unguarded, 1);
    let (expected, got) = (reference.fragments[1], without_guard.fragments[1]);
    eprintln!(
        "{}: without the guard band view 1 keeps {got} of {expected} fragments",
        gpu.info().driver
    );
    if quirk {
        assert!(
            got < expected / 2,
            "{}: the quirk no longer shows ({got} of {expected}); drop it",
            gpu.info().driver
        );
    } else {
        assert_eq!(
            got,
            expected,
            "{}: multiview loses view-1 fragments; add the quirk",
            gpu.info().driver
        );
    }
}

/// Two-pass stereo into one layered image, each eye pass writing its own layer. Without MSAA
/// there is no resolve, so every driver renders it right: the layered frame equals the
/// multiview frame. With 4× MSAA, `layered_resolve_ignores_base_layer` is measured, not
/// assumed: planned without the quirk, a driver that has it resolves the right eye into layer
/// 0, so the right eye stays empty (sky) while planned with it (one image per eye) the frame is
/// right. Mutation: a two-pass layered plan resolving both eyes into layer 0, or a quirk the
/// driver no longer has, fails it.
#[test]
fn layered_two_pass_and_the_resolve_quirk() {
    let gpu = gpu();
    let scene = foveate::scene::default_scene();
    let config = |stereo, msaa| RenderConfig {
        stereo,
        msaa,
        resolution: Some(Resolution::square(64)),
        ..RenderConfig::default()
    };
    let mut unquirked = gpu.caps().clone();
    unquirked.quirks.layered_resolve_ignores_base_layer = false;
    let layered = foveate::plan(&scene, &config(StereoMode::TwoPass, 1), &unquirked).unwrap();
    assert_eq!(layered.layout, foveate::plan::TargetLayout::Layered);
    let (image, _) = render_plan(&gpu, &scene, &layered, 1);
    let multiview = foveate::plan(&scene, &config(StereoMode::Multiview, 1), gpu.caps()).unwrap();
    let (reference, _) = render_plan(&gpu, &scene, &multiview, 1);
    for eye in foveate::view::Eye::BOTH {
        let ssim = reference.eye(eye).ssim(image.eye(eye)).unwrap();
        assert!(ssim > 0.995, "{eye:?}: layered two-pass SSIM {ssim}");
    }

    let quirk = gpu.caps().quirks.layered_resolve_ignores_base_layer;
    let at_4x = foveate::plan(&scene, &config(StereoMode::TwoPass, 4), &unquirked).unwrap();
    let (unguarded, _) = render_plan(&gpu, &scene, &at_4x, 1);
    let planned = foveate::plan(&scene, &config(StereoMode::TwoPass, 4), gpu.caps()).unwrap();
    let (right, _) = render_plan(&gpu, &scene, &planned, 1);
    assert_eq!(
        planned.layout == foveate::plan::TargetLayout::PerEye,
        quirk,
        "the plan reads the quirk"
    );
    let right_eye_ssim = right.right.ssim(&unguarded.right).unwrap();
    eprintln!(
        "{}: layered 4x resolve, right eye SSIM {right_eye_ssim:.4} against one image per eye",
        gpu.info().driver
    );
    if quirk {
        assert!(
            right_eye_ssim < 0.9,
            "{}: the quirk no longer shows (right eye SSIM {right_eye_ssim}); drop it",
            gpu.info().driver
        );
    } else {
        assert!(
            right_eye_ssim > 0.995,
            "{}: the right eye's resolve lands elsewhere; add the quirk",
            gpu.info().driver
        );
    }
}

/// What one query recorded *outside* a render pass, right after a multiview pass of `views`
/// views, writes: how many consecutive slots of its pool become available. The spec gives such
/// a query one slot (only a query inside a multiview pass spans the views); lavapipe 25.0 (not
/// 22.3) keeps the ended pass's view mask and writes one slot per view, past the end of a pool
/// sized by the spec — the crash foveate once hit. Raw Vulkan, nothing of foveate's renderer, so
/// this is the driver's behaviour alone: the pool has spare slots, so the extra writes land
/// inside it and can be counted.
fn slots_written_after_multiview(gpu: &Gpu, views: u32, query: vk::QueryType) -> u32 {
    const SLOTS: u32 = 8;
    let device = gpu.device();
    let image = Image::new(
        gpu,
        &ImageDesc {
            name: "multiview probe",
            format: vk::Format::R8G8B8A8_UNORM,
            width: 4,
            height: 4,
            layers: views,
            samples: 1,
            mip_levels: 1,
            usage: vk::ImageUsageFlags::COLOR_ATTACHMENT,
        },
    )
    .unwrap();
    let view_info = vk::ImageViewCreateInfo::default()
        .image(image.raw())
        .view_type(vk::ImageViewType::TYPE_2D_ARRAY)
        .format(vk::Format::R8G8B8A8_UNORM)
        .subresource_range(vk::ImageSubresourceRange {
            aspect_mask: vk::ImageAspectFlags::COLOR,
            base_mip_level: 0,
            level_count: 1,
            base_array_layer: 0,
            layer_count: views,
        });
    let attachment = [vk::AttachmentDescription::default()
        .format(vk::Format::R8G8B8A8_UNORM)
        .samples(vk::SampleCountFlags::TYPE_1)
        .load_op(vk::AttachmentLoadOp::CLEAR)
        .store_op(vk::AttachmentStoreOp::STORE)
        .initial_layout(vk::ImageLayout::UNDEFINED)
        .final_layout(vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL)];
    let colour = [vk::AttachmentReference::default()
        .attachment(0)
        .layout(vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL)];
    let subpass = [vk::SubpassDescription::default()
        .pipeline_bind_point(vk::PipelineBindPoint::GRAPHICS)
        .color_attachments(&colour)];
    let masks = [(1u32 << views) - 1];
    let mut multiview = vk::RenderPassMultiviewCreateInfo::default()
        .view_masks(&masks)
        .correlation_masks(&masks);
    let info = vk::RenderPassCreateInfo::default()
        .attachments(&attachment)
        .subpasses(&subpass)
        .push_next(&mut multiview);
    // SAFETY (this function): every handle is created here, used by one waited submission and
    // destroyed before returning.
    let render_pass = unsafe { device.create_render_pass(&info, None) }.unwrap();
    let view = unsafe { device.create_image_view(&view_info, None) }.unwrap();
    let views_raw = [view];
    let fb_info = vk::FramebufferCreateInfo::default()
        .render_pass(render_pass)
        .attachments(&views_raw)
        .width(4)
        .height(4)
        .layers(1);
    let framebuffer = unsafe { device.create_framebuffer(&fb_info, None) }.unwrap();
    let mut pool_info = vk::QueryPoolCreateInfo::default()
        .query_type(query)
        .query_count(SLOTS);
    if query == vk::QueryType::PIPELINE_STATISTICS {
        pool_info = pool_info
            .pipeline_statistics(vk::QueryPipelineStatisticFlags::INPUT_ASSEMBLY_PRIMITIVES);
    }
    let pool = unsafe { device.create_query_pool(&pool_info, None) }.unwrap();
    gpu.one_shot(|cmd| unsafe {
        device.cmd_reset_query_pool(cmd, pool, 0, SLOTS);
        let clear = [vk::ClearValue::default()];
        let begin = vk::RenderPassBeginInfo::default()
            .render_pass(render_pass)
            .framebuffer(framebuffer)
            .render_area(vk::Rect2D {
                offset: vk::Offset2D::default(),
                extent: vk::Extent2D {
                    width: 4,
                    height: 4,
                },
            })
            .clear_values(&clear);
        device.cmd_begin_render_pass(cmd, &begin, vk::SubpassContents::INLINE);
        device.cmd_end_render_pass(cmd);
        // Slot 0, outside any render pass: one slot by the spec.
        if query == vk::QueryType::TIMESTAMP {
            device.cmd_write_timestamp(cmd, vk::PipelineStageFlags::BOTTOM_OF_PIPE, pool, 0);
        } else {
            device.cmd_begin_query(cmd, pool, 0, vk::QueryControlFlags::empty());
            device.cmd_end_query(cmd, pool, 0);
        }
    })
    .unwrap();
    let available = (0..SLOTS)
        .filter(|&slot| {
            let mut result = [[0u64; 2]];
            // NOT_READY (an unwritten slot) still fills the availability word.
            let _ = unsafe {
                device.get_query_pool_results(
                    pool,
                    slot,
                    &mut result,
                    vk::QueryResultFlags::TYPE_64 | vk::QueryResultFlags::WITH_AVAILABILITY,
                )
            };
            result[0][1] != 0
        })
        .count() as u32;
    unsafe {
        device.destroy_query_pool(pool, None);
        device.destroy_framebuffer(framebuffer, None);
        device.destroy_image_view(view, None);
        device.destroy_render_pass(render_pass, None);
    }
    assert_validation_clean(gpu);
    available
}

/// That crash, reproduced without foveate's renderer and priced exactly: after a
/// multiview pass, a timestamp or a pipeline-statistics query recorded outside any pass writes
/// one slot on a driver without `queries_after_multiview_span_views`, one per view on one with
/// it (lavapipe 25.0.7: a pool sized for one slot per query is overrun and the driver's worker
/// thread segfaults). The quirk table must agree with what this driver does; mutation: the
/// quirk keyed to the wrong Mesa versions fails it on one of the two CI drivers.
#[test]
fn queries_after_a_multiview_pass_write_what_the_quirk_says() {
    let gpu = gpu();
    let quirk = gpu.caps().quirks.queries_after_multiview_span_views;
    for query in [vk::QueryType::TIMESTAMP, vk::QueryType::PIPELINE_STATISTICS] {
        for views in [2, 4] {
            let written = slots_written_after_multiview(&gpu, views, query);
            eprintln!(
                "{}: a {query:?} after a {views}-view pass wrote {written} slot(s)",
                gpu.info().driver
            );
            let expected = if quirk { views } else { 1 };
            assert_eq!(
                written,
                expected,
                "{}: a {query:?} after a {views}-view pass wrote {written} slots (quirk {})",
                gpu.info().driver,
                if quirk { "on" } else { "off" }
            );
        }
    }
}

/// `multiview_runs_views_serially` is measured, not assumed: a driver that replays a multiview
/// pass per view assembles each primitive once per view (pipeline statistics), one that
/// broadcasts assembles it once. Mutation: the quirk off for lavapipe fails it.
#[test]
fn multiview_replays_each_view_as_the_quirk_says() {
    let gpu = gpu();
    let scene = foveate::scene::default_scene();
    let assembled = |stereo| {
        let config = RenderConfig {
            stereo,
            msaa: 1,
            resolution: Some(Resolution::square(32)),
            count_fragments: true,
            ..RenderConfig::default()
        };
        let plan = foveate::plan(&scene, &config, gpu.caps()).unwrap();
        let (_, stats) = render_plan(&gpu, &scene, &plan, 1);
        stats.pass_statistics[0].assembled
    };
    // Two-pass: its first pass is the left eye's, every triangle once.
    let (multiview, one_view) = (
        assembled(StereoMode::Multiview),
        assembled(StereoMode::TwoPass),
    );
    let expected = if gpu.caps().quirks.multiview_runs_views_serially {
        2
    } else {
        1
    };
    eprintln!(
        "{}: a 2-view pass assembled {multiview} primitives, one view {one_view}",
        gpu.info().driver
    );
    assert_eq!(
        multiview,
        expected * one_view,
        "{}: a 2-view pass assembled {multiview} primitives, one view {one_view}",
        gpu.info().driver
    );
}

/// `anisotropic_filtering_is_slow` is measured, not assumed: a lit atrium frame sampled 8×
/// anisotropically against the same frame trilinear, frames interleaved (so the machine's drift
/// hits both alike), medians of three after a warm-up. Lavapipe 22.3 takes 8–11× as long at
/// this size, 25.0 no longer; the bounds leave a wide margin for a busy machine. Mutation: the
/// quirk's release bound moved fails it on one of the two CI drivers.
#[test]
fn anisotropic_filtering_costs_what_the_quirk_says() {
    let gpu = gpu();
    let atrium = foveate::scene::atrium_scene();
    let config = RenderConfig {
        msaa: 1,
        resolution: Some(Resolution::square(48)),
        ..RenderConfig::default()
    };
    let mut renderers = [true, false].map(|slow| {
        let mut caps = gpu.caps().clone();
        caps.quirks.anisotropic_filtering_is_slow = slow;
        let plan = foveate::plan(&atrium, &config, &caps).unwrap();
        assert_eq!(plan.anisotropy.is_some(), !slow, "the plan reads the quirk");
        foveate::render::Renderer::new(&gpu, &plan, &atrium).unwrap()
    });
    let mut times = [vec![], vec![]];
    for frame in 0..4 {
        for (renderer, times) in renderers.iter_mut().zip(&mut times) {
            let ms = renderer.render_frame(atrium.head).unwrap().frame_ms;
            if frame > 0 {
                times.push(ms);
            }
        }
    }
    drop(renderers);
    assert_validation_clean(&gpu);
    let [trilinear, anisotropic] = times.map(|t| {
        foveate::metrics::Stats::of(&t)
            .expect("three frames")
            .median
    });
    let ratio = anisotropic / trilinear;
    let driver = &gpu.info().driver;
    eprintln!("{driver}: anisotropic {anisotropic:.1} ms, trilinear {trilinear:.1} ms");
    if gpu.caps().quirks.anisotropic_filtering_is_slow {
        assert!(
            ratio > 5.0,
            "{driver}: anisotropic {anisotropic:.1} ms against trilinear {trilinear:.1} ms; drop the quirk"
        );
    } else {
        assert!(
            ratio < 2.5,
            "{driver}: anisotropic {anisotropic:.1} ms against trilinear {trilinear:.1} ms; add the quirk"
        );
    }
}

/// The driver's `FRAGMENT_SHADER_INVOCATIONS` statistic, which counting frames report beside
/// the exact atomic counts, never claims fewer invocations than the pixels the pass shaded
/// (lavapipe 22.3 counts raster blocks: 5–6× on the atrium; 25.0 is exact at 1× MSAA and
/// about 1.45× at 4×). Mutation: the statistic read from the wrong slot of the query (one of
/// the primitive counts) fails it on the fill scene's full-view walls.
#[test]
fn fragment_invocation_statistic_never_undercounts_the_pixels_shaded() {
    let gpu = gpu();
    let runs = [
        (foveate::scene::atrium_scene(), 1, StereoMode::Multiview),
        (foveate::scene::atrium_scene(), 4, StereoMode::TwoPass),
        (foveate::scene::fill_scene(), 1, StereoMode::Multiview),
    ];
    for (scene, msaa, stereo) in runs {
        let config = RenderConfig {
            stereo,
            msaa,
            resolution: Some(Resolution::square(96)),
            count_fragments: true,
            ..RenderConfig::default()
        };
        let plan = foveate::plan(&scene, &config, gpu.caps()).unwrap();
        let (_, stats) = render_plan(&gpu, &scene, &plan, 1);
        for (pass, statistic) in plan.passes.iter().zip(&stats.pass_statistics) {
            let shaded: u64 = stats
                .steps
                .iter()
                .filter(|s| s.pass == pass.name)
                .flat_map(|s| s.views)
                .sum();
            let ratio = statistic.fragment_invocations as f64 / shaded as f64;
            eprintln!("{msaa}x {}: statistic / exact = {ratio:.3}", pass.name);
            assert!(
                shaded > 0 && statistic.fragment_invocations >= shaded,
                "{}: {} counted {} invocations for {shaded} shaded pixels",
                gpu.info().driver,
                pass.name,
                statistic.fragment_invocations
            );
        }
    }
}
