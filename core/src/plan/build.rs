//! Planning a frame: validate the configuration, then let each technique's builder add its
//! passes and steps (`stereo_scene`, `mffr`, `composition`, `counting`), then derive ops,
//! layouts and clear values (`derive`).

use super::barriers::derive_barriers;
use super::config::RadialDensityGeometry;
use super::counting::plan_counting;
use super::derive::{assign_stencil, derive_ops};
use super::masks::{add_mask_fans, mask_pipeline};
use super::mffr::{add_far_composite, far_composite_pipeline, far_pass};
use super::model::*;
use super::ops::AttachmentId;
use super::output::{
    apply_output_format, check_external_output, output_pass, output_pipeline,
    periphery_accumulation_pass,
};
use super::pipeline::{PipelineDesc, StepContext};
use super::probe::{add_probe, probe_pipeline};
use super::radial_density::{add_radial_density, radial_mask_pipeline, reconstruct_pipeline};
use super::scene_sizes::{lod_plan, plan_instance_buffers, spare_total};
use super::split_views::{layer_copy_pipeline, one_pass_per_view};
use super::steps::{DrawSet, OutputSource, Step};
use super::stereo_scene::{scene_passes, scene_pipeline, FoveaPasses, ViewSet};
use super::temporal::{add_accumulation, history_size, periphery_image};
use super::validate::*;
use super::{
    ConfigError, DeviceCaps, FoveaLayout, OutputStage, RenderConfig, Resolution, StereoMode,
};
use crate::foveation::{FoveationGeometry, HistoryAt};
use crate::mffr::MffrGeometry;
use crate::scene::{Scene, Shading, MAX_POINT_LIGHTS};
use crate::view::{Eye, EyeParams, HmdProfile, LensRegion};

/// Plans a frame. Rejects a configuration the device or foveate cannot render with an error
/// naming the field, the value and the limit.
pub fn plan(
    scene: &Scene,
    config: &RenderConfig,
    caps: &DeviceCaps,
) -> Result<FramePlan, ConfigError> {
    plan_with(scene, false, config, caps)
}

/// Plans a frame of `scene`, or (`engine`) one whose scene steps an engine draws, `scene`
/// then empty (see `plan::plan_for_engine`).
pub(super) fn plan_with(
    scene: &Scene,
    engine: bool,
    config: &RenderConfig,
    caps: &DeviceCaps,
) -> Result<FramePlan, ConfigError> {
    let e = resolve_effects(scene, config, caps)?;
    let layout = target_layout(config.stereo, caps);
    let mut attachments = Vec::new();
    let render_resolution = e.foveation.map_or(e.eye_resolution, |f| f.periphery_view);
    let far = e
        .mffr
        .map(|g| far_pass(config, g.resolution, &mut attachments));
    let far_colour = far
        .as_ref()
        .map(|p| p.resolve.unwrap_or(p.color).attachment);
    let fovea_layout = fovea_layout_of(&e, config, (!engine).then_some(scene), caps);
    let mut passes: Vec<PassPlan> = far.into_iter().collect();
    passes.extend(scene_passes(
        config,
        render_resolution,
        layout,
        far_colour,
        fovea_layout
            .as_ref()
            .zip(e.foveation.as_ref())
            .map(|(c, f)| fovea_passes(c, f, config.msaa)),
        &mut attachments,
    ));
    let lens = config.output == OutputStage::Lens;
    let techniques = Techniques {
        config,
        eye_resolution: e.eye_resolution,
        layout,
        foveation: e.foveation.as_ref(),
        fovea_layout: fovea_layout.as_ref(),
        mffr: e.mffr.as_ref(),
        radial_density: e.radial_density.is_some(),
    };
    let (history, depth_history) =
        add_technique_steps(&techniques, &mut passes, &mut attachments).unzip();
    if caps.quirks.multiview_clipping_drops_views {
        if engine {
            let resolve_lands_in_layer_0 = caps.quirks.layered_resolve_ignores_base_layer;
            passes = one_pass_per_view(passes, &mut attachments, resolve_lands_in_layer_0)?;
        }
        work_around_multiview_clipping(&mut passes, &attachments, caps);
    }
    let lit = scene.shading() == Shading::Lit;
    let mut plan = FramePlan {
        hmd: e.hmd,
        eyes: e.eyes,
        eye_resolution: e.eye_resolution,
        stereo: config.stereo,
        // The parafoveal ring's two views render in the fovea's pass.
        views: config.view_count() + 2 * e.foveation.is_some_and(|f| f.ring.is_some()) as u32,
        samples: config.msaa,
        near: config.near,
        far: scene.reach.map_or(config.far, |r| config.far.max(r)),
        layout,
        attachments,
        passes,
        buffers: Vec::new(),
        timestamp_queries: 0,
        statistics_queries: 0,
        query_spare_slots: 0,
        counted: Vec::new(),
        draw_calls_estimate: 0,
        foveation: e.foveation,
        hmd_mask: e.hmd_mask,
        mffr: e.mffr,
        culling: config.culling,
        radial_density: e.radial_density,
        cull_slots: Vec::new(),
        clusters: None,
        lod: lod_plan(config, scene),
        scene_instances: scene.instance_count() + spare_total(scene, config.spare_instances),
        spare_instances: config.spare_instances,
        fovea_layout,
        lit,
        point_lights: if lit { scene.lights.len() as u32 } else { 0 },
        alpha_mask: scene.materials.iter().any(|m| m.alpha_cutoff.is_some()),
        anisotropy: (caps.max_anisotropy >= 2.0 && !caps.quirks.anisotropic_filtering_is_slow)
            .then(|| caps.max_anisotropy.min(8.0)),
        lens: lens.then(|| LensOutput::new(e.hmd.distortion, &e.eyes)),
        external_output: config.external_output,
        engine_draws: engine,
        hidden_area_mesh: config.hidden_area_mesh,
        frame_slots: config.frames_in_flight,
        history,
        depth_history,
    };
    check_external_output(&plan)?;
    // An engine's scene steps draw what the engine culls: no cull slot of foveate's.
    if !engine {
        assign_cull_slots(&mut plan);
    }
    plan.draw_calls_estimate = draw_calls_estimate(scene, &plan);
    plan_queries(&mut plan, config, caps);
    plan_instance_buffers(&mut plan, scene, caps, config);
    apply_output_format(&mut plan, config.output_format);
    assign_stencil(&mut plan);
    // The frame before's periphery depth is an image like this frame's.
    if let Some(h) = plan.depth_history {
        plan.attachments[h.read].format = plan.attachments[h.written].format;
    }
    check_depth_stencil(&plan, config, caps)?;
    derive_ops(&mut plan);
    for (pass, barriers) in derive_barriers(&plan).into_iter().enumerate() {
        plan.passes[pass].barriers = barriers;
    }
    for pass in 0..plan.passes.len() {
        plan.passes[pass].pipelines = step_pipelines(&plan, pass);
    }
    Ok(plan)
}

/// Where each eye's image lies: one layered image, an image per eye where the driver cannot
/// resolve into a layer, or side by side for the techniques that draw both eyes in one view.
fn target_layout(stereo: StereoMode, caps: &DeviceCaps) -> TargetLayout {
    match stereo {
        StereoMode::Multiview => TargetLayout::Layered,
        StereoMode::TwoPass if caps.quirks.layered_resolve_ignores_base_layer => {
            TargetLayout::PerEye
        }
        StereoMode::TwoPass => TargetLayout::Layered,
        StereoMode::PerObject | StereoMode::Instanced => TargetLayout::SideBySide,
    }
}

/// Each step's pipeline, as the builder that added the step states it.
fn step_pipelines(plan: &FramePlan, pass_index: usize) -> Vec<PipelineDesc> {
    let pass = &plan.passes[pass_index];
    let radial = || {
        plan.radial_density
            .as_ref()
            .expect("planned with radial density")
    };
    pass.steps
        .iter()
        .map(|step| {
            let ctx = StepContext {
                counter_base: plan.counter_base(pass_index, step.counted()),
                guard_band: pass.guard_band,
                first_view: pass.first_view,
                stencil: step.stencil(),
            };
            match step {
                Step::MaskFans { .. } => mask_pipeline(&ctx),
                Step::FarComposite { .. } => far_composite_pipeline(&ctx, plan, pass),
                Step::Scene {
                    draw_set,
                    cull_slot,
                    ..
                } => scene_pipeline(&ctx, plan, pass, *draw_set, cull_slot.is_some()),
                Step::Probe { .. } => probe_pipeline(&ctx),
                Step::Output(output) => output_pipeline(&ctx, output, plan),
                Step::RadialMask { .. } => radial_mask_pipeline(&ctx, radial()),
                Step::Reconstruct => reconstruct_pipeline(&ctx, radial()),
                Step::LayerCopy { .. } => layer_copy_pipeline(&ctx),
            }
        })
        .collect()
}

/// What the configuration's effects resolve to for this headset, resolution and scene, each
/// validated.
struct Effects {
    hmd: &'static HmdProfile,
    eyes: EyeParams,
    eye_resolution: Resolution,
    foveation: Option<FoveationGeometry>,
    hmd_mask: Option<[LensRegion; 2]>,
    mffr: Option<MffrGeometry>,
    radial_density: Option<RadialDensityGeometry>,
}

fn resolve_effects(
    scene: &Scene,
    config: &RenderConfig,
    caps: &DeviceCaps,
) -> Result<Effects, ConfigError> {
    let hmd = config.hmd_profile()?;
    let eyes = validate_eyes(config, hmd)?;
    let eye_resolution = validate_resolution(config, hmd, caps)?;
    validate_views(config, caps)?;
    let foveation = config
        .foveation
        .map(|f| f.geometry(eye_resolution))
        .transpose()?;
    validate_msaa(config, caps)?;
    if let Some(f) = &foveation {
        validate_view_sets(config, f, caps)?;
    }
    validate_depth_range(config)?;
    validate_frames_in_flight(config)?;
    validate_spare_instances(config)?;
    validate_features(config, caps)?;
    validate_culling(config)?;
    if scene.lights.len() > MAX_POINT_LIGHTS {
        return Err(ConfigError::new(
            "scene lights",
            scene.lights.len(),
            format!("at most {MAX_POINT_LIGHTS} point lights"),
        ));
    }
    let prefilter = config.foveation.is_some_and(|f| f.periphery_prefilter);
    if prefilter && scene.shading() != Shading::Lit {
        return Err(ConfigError::new(
            "periphery_prefilter",
            "true",
            "a lit scene (a flat one has no highlights to widen)",
        ));
    }
    let hmd_mask = config
        .hmd_mask
        .then(|| Eye::BOTH.map(|e| hmd.lens_region(eyes.fov(e))));
    let mffr = match config.mffr {
        Some(m) => MffrGeometry::resolve(m, &eyes, eye_resolution, config.near, config.far)?
            // A scene whose every point is nearer than the split has no far field to render.
            .filter(|g| scene.content_reach() > g.split_m),
        None => None,
    };
    if let Some(g) = &mffr {
        let max = caps.max_image_dimension_2d;
        if g.resolution.width > max || g.resolution.height > max {
            return Err(ConfigError::new(
                "mffr split",
                g.config.split,
                format!(
                    "a far image within {max}x{max} on this device; it needs {}",
                    g.resolution
                ),
            ));
        }
    }

    let radial_density = config
        .radial_density
        .map(|r| r.resolve(hmd, &eyes, eye_resolution))
        .transpose()?;
    Ok(Effects {
        hmd,
        eyes,
        eye_resolution,
        foveation,
        hmd_mask,
        mffr,
        radial_density,
    })
}

/// What the technique builders need to know of the frame.
struct Techniques<'a> {
    config: &'a RenderConfig,
    eye_resolution: Resolution,
    layout: TargetLayout,
    foveation: Option<&'a FoveationGeometry>,
    fovea_layout: Option<&'a FoveaLayoutChoice>,
    mffr: Option<&'a MffrGeometry>,
    radial_density: bool,
}

/// Each technique's steps around the scene step of every eye pass, then its passes: radial
/// density's reconstruction, the output stage (with temporal accumulation folded in: its
/// history pair is returned).
fn add_technique_steps(
    t: &Techniques,
    passes: &mut Vec<PassPlan>,
    attachments: &mut Vec<AttachmentPlan>,
) -> Option<(HistoryPair, HistoryPair)> {
    let (config, eye_resolution, layout) = (t.config, t.eye_resolution, t.layout);
    let (foveation, fovea_layout, mffr) = (t.foveation, t.fovea_layout, t.mffr);
    let lens = config.output == OutputStage::Lens;
    let masks = config.hmd_mask || foveation.is_some_and(|f| f.stencil);
    for pass in passes.iter_mut().filter(|p| p.kind == PassKind::Scene) {
        if masks {
            add_mask_fans(pass, config.hidden_area_mesh);
        }
        if let Some(g) = mffr {
            add_far_composite(pass, g.config.order);
        }
        if config.coverage_probe {
            add_probe(pass);
        }
    }
    // The output stage: composition folds into it; the lens asks for it on every frame.
    if t.radial_density {
        add_radial_density(passes, attachments, eye_resolution);
    }
    let source = match (fovea_layout, layout) {
        (Some(c), _) => Some(OutputSource::Foveated {
            fovea_layer: if c.layout == FoveaLayout::TwoPass {
                0
            } else {
                2
            },
            sharpen: foveation.is_some_and(|f| f.periphery_sharpen > 0.0),
        }),
        _ if !lens => None,
        _ if t.radial_density => Some(OutputSource::Layered),
        (None, TargetLayout::Layered) => Some(OutputSource::Layered),
        (None, TargetLayout::PerEye) => Some(OutputSource::PerEye),
        (None, TargetLayout::SideBySide) => Some(OutputSource::SideBySide),
    };
    let source = source?;
    let mut images: Vec<AttachmentId> = (0..attachments.len())
        .filter(|&i| attachments[i].read_after_frame)
        .collect();
    // The periphery accumulated over frames: in the output pass, which samples the history and
    // the periphery's depth after its sources and writes the next history beside the output;
    // or in a pass of its own (at the periphery's texels or the history's density) whose image
    // the output pass then composes as it would a single frame's periphery.
    let temporal = foveation.and_then(|f| f.temporal);
    let periphery = temporal
        .filter(|t| t.history_at == HistoryAt::Periphery)
        .and_then(|_| periphery_image(passes, attachments));
    let size = history_size(temporal, periphery.map(|(_, size, _)| size), eye_resolution);
    let accumulation = temporal.and_then(|t| add_accumulation(passes, attachments, size, t));
    let in_output = accumulation.is_some() && periphery.is_none();
    match (&accumulation, periphery) {
        (Some(a), Some((_, _, format))) => {
            let mut sources = images.clone();
            sources.extend(a.samples());
            let mut pass = periphery_accumulation_pass(sources, source, size, format, attachments);
            pass.history = Some(a.written());
            images = vec![pass.color.attachment, *images.last()?];
            passes.push(pass);
        }
        (Some(a), None) => images.extend(a.samples()),
        (None, _) => {}
    }
    let mut output = output_pass(images, source, lens, in_output, eye_resolution, attachments);
    output.history = accumulation
        .as_ref()
        .filter(|_| in_output)
        .map(|a| a.written());
    passes.push(output);
    accumulation.map(|a| (a.pair, a.depth))
}

/// A driver that clips multiview primitives into view 0 gets a guard band on every multiview
/// pass, and depth clamping at the MFFR split (see [`DriverQuirks`](super::DriverQuirks)).
fn work_around_multiview_clipping(
    passes: &mut [PassPlan],
    attachments: &[AttachmentPlan],
    caps: &DeviceCaps,
) {
    for p in passes.iter_mut().filter(|p| p.view_mask.count_ones() > 1) {
        let a = &attachments[p.color.attachment];
        p.guard_band = guard_band(
            Resolution {
                width: a.width,
                height: a.height,
            },
            caps,
        );
        // Clipping at the MFFR split would drop views too: clamp depth instead, so what lies
        // beyond the split lands on the far plane's depth, 0, and fails the depth test
        // against the clear value (reverse-Z, GREATER) without any primitive being clipped.
        p.depth_clamp = p.far_composite().is_some() && caps.depth_clamp;
    }
}

/// Timestamps (one before the frame, one after each pass), a counting frame's pipeline
/// statistics, and spare slots where a driver quirk writes past a query.
fn plan_queries(plan: &mut FramePlan, config: &RenderConfig, caps: &DeviceCaps) {
    if config.timestamps {
        // One before the frame and one after each pass.
        plan.timestamp_queries = plan.passes.len() as u32 + 1;
    }
    if config.count_fragments {
        plan_counting(plan);
        if caps.pipeline_statistics {
            plan.statistics_queries = plan.passes.len() as u32;
        }
    }
    let queries = plan.timestamp_queries + plan.statistics_queries;
    if caps.quirks.queries_after_multiview_span_views && queries > 0 {
        let most_views = plan.passes.iter().map(|p| p.view_mask.count_ones());
        plan.query_spare_slots = most_views.max().unwrap_or(1).saturating_sub(1);
    }
}

/// A foveated frame's view pairs as its scene passes render them.
fn fovea_passes(c: &FoveaLayoutChoice, f: &FoveationGeometry, msaa: u32) -> FoveaPasses {
    FoveaPasses {
        layout: c.layout,
        cull: c.cull,
        periphery: ViewSet {
            resolution: f.periphery_view,
            samples: f.periphery_samples(msaa),
        },
        fovea: ViewSet {
            resolution: f.fovea_view,
            samples: msaa,
        },
        ring: f.ring.is_some(),
    }
}

/// A foveated frame's layout for `scene` (`None`: an engine's draws).
fn fovea_layout_of(
    e: &Effects,
    config: &RenderConfig,
    scene: Option<&Scene>,
    caps: &DeviceCaps,
) -> Option<FoveaLayoutChoice> {
    let f = e.foveation?;
    // The fovea's pass renders the ring's wider views too: it draws what the periphery draws.
    let cull = f.cull_fovea && e.mffr.is_none() && f.ring.is_none();
    let differ = f.views_differ(config.msaa);
    let triangles = scene.map(|s| s.triangle_count() as u64);
    let choice = choose_fovea_layout(
        config.fovea_layout,
        cull,
        differ,
        triangles,
        f.fovea_view,
        caps,
    );
    // An engine culls each pass against its views itself; one pass for all four views then
    // draws the same in each (no per-view tags: those are foveate's culled ids).
    let engine_one_pass = scene.is_none() && choice.layout == FoveaLayout::OnePass;
    Some(FoveaLayoutChoice {
        cull: choice.cull && !engine_one_pass,
        ..choice
    })
}

/// The layout of a foveated frame's views: as asked, or chosen from the device's quirks and the
/// scene's geometry (`triangles` per view; `None`: an engine's, unknown) against the fovea
/// views' pixels, with the reason.
fn choose_fovea_layout(
    asked: FoveaLayout,
    cull: bool,
    views_differ: bool,
    triangles: Option<u64>,
    view: Resolution,
    caps: &DeviceCaps,
) -> FoveaLayoutChoice {
    let pixels = view.width as u64 * view.height as u64;
    let (layout, reason) = match asked {
        FoveaLayout::OnePass | FoveaLayout::TwoPass => (asked, format!("asked for ({asked})")),
        FoveaLayout::Auto if views_differ => (
            FoveaLayout::TwoPass,
            "the periphery and fovea views differ in size or samples (or the fovea's pass renders \
             the parafoveal ring too), so each pair renders into images of its own"
                .to_string(),
        ),
        FoveaLayout::Auto if !cull => (
            FoveaLayout::OnePass,
            "the fovea views draw what the periphery draws (fovea culling off, or MFFR's near \
             field), so one 4-view pass binds and submits the scene once"
                .to_string(),
        ),
        FoveaLayout::Auto if caps.quirks.multiview_runs_views_serially => (
            FoveaLayout::TwoPass,
            format!(
                "{} runs multiview views one after another: a separate 2-view fovea pass adds no \
                 per-view work and skips every vertex of the instances the fovea misses",
                caps.device_name
            ),
        ),
        FoveaLayout::Auto if triangles.is_none() => (
            FoveaLayout::OnePass,
            "an engine draws the scene: one 4-view pass takes its draws once, and the fovea views \
             show what the periphery views show"
                .to_string(),
        ),
        FoveaLayout::Auto if triangles > Some(pixels) => (
            FoveaLayout::TwoPass,
            format!(
                "vertex-bound: {} triangles per view exceed a view's {pixels} pixels, so \
                 skipping the fovea-culled instances' vertices outweighs a second pass",
                triangles.unwrap_or(0)
            ),
        ),
        FoveaLayout::Auto => (
            FoveaLayout::OnePass,
            format!(
                "fragment-bound: {} triangles per view against a view's {pixels} pixels; \
                 one 4-view pass bins the scene once, fovea-culled instances emit no primitives \
                 in the fovea views",
                triangles.unwrap_or(0)
            ),
        ),
    };
    FoveaLayoutChoice {
        layout,
        cull,
        reason,
    }
}

/// One cull slot per distinct culled draw set, in pass order (at most two: both eyes' set,
/// each eye's own, MFFR's near and far fields, or the periphery's and the fovea's), and each
/// scene step pointed at its slot. With level of detail every set is chosen per frame, so the
/// unculled set (`All`) has a slot too.
fn assign_cull_slots(plan: &mut FramePlan) {
    let mut slots: Vec<DrawSet> = Vec::new();
    for pass in &mut plan.passes {
        for step in &mut pass.steps {
            if let Step::Scene {
                draw_set,
                cull_slot,
                ..
            } = step
            {
                if *draw_set == DrawSet::All && plan.lod.is_none() {
                    continue;
                }
                let slot = slots.iter().position(|s| s == draw_set).unwrap_or_else(|| {
                    slots.push(*draw_set);
                    slots.len() - 1
                });
                *cull_slot = Some(slot);
            }
        }
    }
    debug_assert!(slots.len() <= 2, "the instance-id buffer holds two sets");
    plan.cull_slots = slots;
}

/// The largest guard band (a power of two up to 8) whose grown viewport the device accepts.
fn guard_band(eye: Resolution, caps: &DeviceCaps) -> u32 {
    let side = eye.width.max(eye.height) as f32;
    let fits = |k: u32| {
        let k = k as f32;
        k * side <= caps.max_viewport_dimension as f32
            && -(k - 1.0) * 0.5 * side >= caps.viewport_bounds.0
            && (k + 1.0) * 0.5 * side <= caps.viewport_bounds.1
    };
    [8, 4, 2].into_iter().find(|&k| fits(k)).unwrap_or(1)
}

/// Draw calls one frame records without culling, estimated: each scene pass's draws of the
/// scene (one per mesh; per object, two per instance), plus the full-view draws of composition
/// and the far composite. Mask fans and probes are left out; the renderer tallies what it
/// records.
fn draw_calls_estimate(scene: &Scene, plan: &FramePlan) -> u64 {
    let meshes = scene.draws().count() as u64;
    plan.passes
        .iter()
        .map(|p| {
            let scene_draws = match p.submission {
                _ if p.kind.is_full_view() => 1,
                Submission::PerObject => 2 * scene.instance_count() as u64,
                _ => meshes,
            };
            scene_draws + p.far_composite().is_some() as u64
        })
        .sum()
}
