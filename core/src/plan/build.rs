//! Planning a frame: validate the configuration, then let each technique's builder add its
//! passes and steps (`stereo_scene`, `mffr`, `composition`, `counting`), then derive ops,
//! layouts and clear values (`derive`).

use super::composition::composite_pass;
use super::counting::plan_counting;
use super::derive::{assign_stencil, derive_ops};
use super::masks::add_mask_fans;
use super::mffr::{add_far_composite, far_pass};
use super::model::*;
use super::probe::add_probe;
use super::radial_density::add_radial_density;
use super::steps::Step;
use super::stereo_scene::scene_passes;
use super::validate::*;
use super::{ConfigError, DeviceCaps, RenderConfig, Resolution, StereoMode};
use crate::mffr::MffrGeometry;
use crate::scene::Scene;
use crate::view::Eye;

/// Plans a frame. Rejects a configuration the device or foveate cannot render with an error
/// naming the field, the value and the limit.
pub fn plan(
    scene: &Scene,
    config: &RenderConfig,
    caps: &DeviceCaps,
) -> Result<FramePlan, ConfigError> {
    let hmd = config.hmd_profile()?;
    let eyes = validate_eyes(config, hmd)?;
    let eye_resolution = validate_resolution(config, hmd, caps)?;
    validate_views(config, caps)?;
    let foveation = config
        .foveation
        .map(|f| f.geometry(eye_resolution))
        .transpose()?;
    validate_msaa(config, caps)?;
    validate_depth_range(config)?;
    validate_features(config, caps)?;
    validate_culling(config)?;
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

    let layout = match config.stereo {
        StereoMode::Multiview => TargetLayout::Layered,
        StereoMode::TwoPass if caps.quirks.layered_resolve_ignores_base_layer => {
            TargetLayout::PerEye
        }
        StereoMode::TwoPass => TargetLayout::Layered,
        StereoMode::PerObject | StereoMode::Instanced => TargetLayout::SideBySide,
    };
    let mut attachments = Vec::new();
    let render_resolution = foveation.map_or(eye_resolution, |f| f.view);
    let far = mffr.map(|g| far_pass(config, g.resolution, &mut attachments));
    let far_colour = far
        .as_ref()
        .map(|p| p.resolve.unwrap_or(p.color).attachment);
    let mut passes: Vec<PassPlan> = far.into_iter().collect();
    passes.extend(scene_passes(
        config,
        render_resolution,
        layout,
        far_colour,
        &mut attachments,
    ));
    // Each technique's steps around the scene step of every eye pass.
    let masks = config.hmd_mask || foveation.is_some_and(|f| f.stencil);
    for pass in passes.iter_mut().filter(|p| p.kind == PassKind::Scene) {
        if masks {
            add_mask_fans(pass);
        }
        if let Some(g) = &mffr {
            add_far_composite(pass, g.config.order);
        }
        if config.coverage_probe {
            add_probe(pass);
        }
    }
    if foveation.is_some() {
        let scene = passes.iter().find(|p| p.kind == PassKind::Scene);
        let composite = composite_pass(
            scene.expect("a foveated frame has its scene pass"),
            eye_resolution,
            &mut attachments,
        );
        passes.push(composite);
    }
    if radial_density.is_some() {
        add_radial_density(&mut passes, &mut attachments, eye_resolution);
    }
    if caps.quirks.multiview_clipping_drops_views {
        for p in passes.iter_mut().filter(|p| p.view_mask != 0) {
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
    let mut plan = FramePlan {
        hmd,
        eyes,
        eye_resolution,
        stereo: config.stereo,
        views: config.views,
        samples: config.msaa,
        near: config.near,
        far: config.far,
        layout,
        attachments,
        passes,
        buffers: Vec::new(),
        timestamp_queries: 0,
        counted: Vec::new(),
        draw_calls_estimate: 0,
        foveation,
        hmd_mask,
        mffr,
        culling: config.culling,
        radial_density,
        cull_slots: Vec::new(),
        scene_instances: scene.instance_count(),
    };
    assign_cull_slots(&mut plan);
    plan.draw_calls_estimate = draw_calls_estimate(scene, &plan);
    if config.timestamps {
        // One before the frame and one after each pass.
        plan.timestamp_queries = plan.passes.len() as u32 + 1;
    }
    if config.count_fragments {
        plan_counting(&mut plan);
    }
    if !plan.cull_slots.is_empty() {
        // Near and far sets of one frame, each at most every instance.
        plan.buffers.push(BufferPlan {
            name: INSTANCE_IDS,
            bytes: 2 * 4 * (scene.instance_count().max(1) as u64),
        });
    }
    assign_stencil(&mut plan);
    derive_ops(&mut plan);
    Ok(plan)
}

/// One cull slot per distinct culled draw set, in pass order (at most two: both eyes' set,
/// each eye's own, or MFFR's near and far fields), and each scene step pointed at its slot.
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
                if *draw_set == DrawSet::All {
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
                _ if matches!(p.kind, PassKind::Composite | PassKind::Reconstruct) => 1,
                Submission::PerObject => 2 * scene.instance_count() as u64,
                _ => meshes,
            };
            scene_draws + p.far_composite().is_some() as u64
        })
        .sum()
}
