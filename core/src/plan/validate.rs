//! Validation: a configuration the device or foveate cannot render is refused with the field,
//! the value and the limit.

use super::model::{Format, FramePlan};
use super::{
    ConfigError, DeviceCaps, FoveaLayout, RenderConfig, Resolution, StereoMode, MAX_VIEWS,
};
use crate::foveation::FoveationGeometry;
use crate::view::{EyeParams, HmdProfile};

pub(super) fn validate_eyes(
    config: &RenderConfig,
    hmd: &HmdProfile,
) -> Result<EyeParams, ConfigError> {
    let ipd = config.ipd_m.unwrap_or(crate::view::DEFAULT_IPD_M);
    if !ipd.is_finite() || !(0.0..=0.1).contains(&ipd) {
        return Err(ConfigError::new(
            "ipd",
            ipd,
            "a finite distance in metres, 0 ≤ ipd ≤ 0.1",
        ));
    }
    let mut eyes = hmd.eyes(ipd);
    if let Some(cant) = config.cant_deg {
        if !cant.is_finite() || cant.abs() > 45.0 {
            return Err(ConfigError::new(
                "cant",
                cant,
                "finite degrees, |cant| ≤ 45",
            ));
        }
        eyes.cant_rad = cant.to_radians();
    }
    if let Some(fov) = config.fov {
        // Each half-angle within (-89°, 89°) and the two halves of an axis spanning > 0.
        let max = 89f32.to_radians().tan();
        let ok = |t: f32| t.is_finite() && t.abs() < max;
        let valid = fov.as_array().into_iter().all(ok)
            && fov.left + fov.right > 0.0
            && fov.up + fov.down > 0.0;
        if !valid {
            return Err(ConfigError::new(
                "fov",
                format!("{:?}", fov.as_array()),
                format!("finite tangents with |t| < {max:.1} (89°) spanning a positive angle on each axis"),
            ));
        }
        eyes.left_fov = fov;
        eyes.right_fov = fov.mirrored();
    }
    Ok(eyes)
}

pub(super) fn validate_resolution(
    config: &RenderConfig,
    hmd: &HmdProfile,
    caps: &DeviceCaps,
) -> Result<Resolution, ConfigError> {
    let res = config.resolution.unwrap_or(Resolution {
        width: hmd.panel_per_eye.0,
        height: hmd.panel_per_eye.1,
    });
    let side_by_side = matches!(config.stereo, StereoMode::PerObject | StereoMode::Instanced);
    let max_width = if side_by_side {
        caps.max_image_dimension_2d / 2
    } else {
        caps.max_image_dimension_2d
    };
    let max_height = caps.max_image_dimension_2d;
    if res.width == 0 || res.height == 0 || res.width > max_width || res.height > max_height {
        let why = if side_by_side {
            " (both eyes share one double-wide image)"
        } else {
            ""
        };
        return Err(ConfigError::new(
            "resolution",
            res,
            format!(
                "each side 1..={} wide and 1..={max_height} high per eye on this device{why}",
                max_width
            ),
        ));
    }
    Ok(res)
}

pub(super) fn validate_views(config: &RenderConfig, caps: &DeviceCaps) -> Result<(), ConfigError> {
    let limit = MAX_VIEWS.min(caps.max_multiview_views);
    let views = config.view_count();
    if views == 0 || views > limit {
        return Err(ConfigError::new(
            "views",
            views,
            format!(
                "at most {limit} (foveate renders up to {MAX_VIEWS} views in one pass; this device's maxMultiviewViewCount is {})",
                caps.max_multiview_views
            ),
        ));
    }
    let wanted = if config.foveation.is_some() { 4 } else { 2 };
    if views != wanted {
        let why = if wanted == 4 {
            "foveated rendering uses exactly 4 views (periphery and fovea per eye); leave views out to derive them"
        } else {
            "stereo rendering uses exactly 2 views (4 with foveation); leave views out to derive them"
        };
        return Err(ConfigError::new("views", views, why));
    }
    if config.foveation.is_some() && config.stereo != StereoMode::Multiview {
        return Err(ConfigError::new(
            "stereo",
            config.stereo,
            "foveation renders its 4 views with multiview",
        ));
    }
    Ok(())
}

pub(super) fn validate_msaa(config: &RenderConfig, caps: &DeviceCaps) -> Result<(), ConfigError> {
    check_samples("msaa", config.msaa, caps)?;
    match config.mffr.and_then(|m| m.far_msaa) {
        Some(far) => check_samples("mffr far_msaa", far, caps),
        None => Ok(()),
    }
}

/// A sample count the frame's passes are built for (1 or 4) that the device supports.
fn check_samples(field: &'static str, samples: u32, caps: &DeviceCaps) -> Result<(), ConfigError> {
    let device: Vec<String> = caps.sample_counts().iter().map(u32::to_string).collect();
    if !matches!(samples, 1 | 4) || !caps.supports_samples(samples) {
        return Err(ConfigError::new(
            field,
            samples,
            format!(
                "1 or 4, and one the device supports (it supports {})",
                device.join(", ")
            ),
        ));
    }
    Ok(())
}

/// A parafoveal ring renders in the fovea's pass, as that pass's views 2, 3: only where that
/// pass is its own.
fn validate_ring(config: &RenderConfig, ratio: f32) -> Result<(), ConfigError> {
    let refused = if config.fovea_layout == FoveaLayout::OnePass {
        Some("the two-pass fovea layout (its fovea pass renders the ring's views too; the one-pass layout has no room for them)")
    } else if config.mffr.is_some() {
        Some("a frame without MFFR (its far field is composed into four views)")
    } else if config.foveation.is_some_and(|f| f.periphery_prefilter) {
        Some("a periphery without the prefilter (the ring is sampled at its own density)")
    } else {
        None
    };
    match refused {
        Some(why) => Err(ConfigError::new("ring_ratio", ratio, why)),
        None => Ok(()),
    }
}

/// A foveated frame whose periphery and fovea views differ in size or samples: only the
/// two-pass layout gives them images of their own, and the device must have the samples.
pub(super) fn validate_view_sets(
    config: &RenderConfig,
    foveation: &FoveationGeometry,
    caps: &DeviceCaps,
) -> Result<(), ConfigError> {
    if let Some(m) = foveation.periphery_msaa {
        if !caps.supports_samples(m) {
            return Err(ConfigError::new(
                "periphery_msaa",
                m,
                "a sample count the device supports",
            ));
        }
    }
    if let Some(r) = foveation.ring {
        validate_ring(config, r.ratio)?;
    }
    if foveation.views_differ(config.msaa) && config.fovea_layout == FoveaLayout::OnePass {
        return Err(ConfigError::new(
            "fovea_layout",
            config.fovea_layout,
            format!(
                "two-pass or auto: periphery views {} at {}x and fovea views {} at {}x need images \
                 of their own, and the one-pass layout renders all four views as layers of one \
                 image (one size, one sample count)",
                foveation.periphery_view,
                foveation.periphery_samples(config.msaa),
                foveation.fovea_view,
                config.msaa
            ),
        ));
    }
    if foveation.temporal.is_some() {
        // The history reprojects each periphery pixel by its depth, read from a single-sample
        // image: a multisampled periphery's depth is resolved to it in the pass.
        let samples = foveation.periphery_samples(config.msaa);
        if samples != 1 && !caps.depth_resolve {
            return Err(ConfigError::new(
                "periphery_msaa",
                samples,
                format!(
                    "1 with temporal accumulation on {} (the reprojection reads one depth per \
                     pixel, and the device cannot resolve a multisampled depth in the pass: \
                     VK_KHR_depth_stencil_resolve is not enabled; an engine's device declares it \
                     with Gpu::from_engine_with_extensions)",
                    caps.device_name
                ),
            ));
        }
        // The output stage accumulates pixel by pixel: it has no accumulated neighbourhood to
        // sharpen or to upscale.
        if foveation.periphery_sharpen > 0.0 {
            return Err(ConfigError::new(
                "periphery_sharpen",
                foveation.periphery_sharpen,
                "0 with temporal accumulation (the accumulated periphery is at the output's \
                 pixels already: nothing to sharpen as it is upscaled)",
            ));
        }
        if foveation.periphery_filter != crate::foveation::PeripheryFilter::Bilinear {
            return Err(ConfigError::new(
                "periphery_filter",
                format!("{:?}", foveation.periphery_filter),
                "bilinear with temporal accumulation (the accumulated periphery is at the \
                 output's pixels already: nothing to upscale)",
            ));
        }
        if config.mffr.is_some() {
            return Err(ConfigError::new(
                "mffr",
                "on",
                "off with temporal accumulation (the far field leaves the periphery no depth to \
                 reproject)",
            ));
        }
    }
    Ok(())
}

pub(super) fn validate_depth_range(config: &RenderConfig) -> Result<(), ConfigError> {
    if !config.near.is_finite() || config.near <= 0.0 {
        return Err(ConfigError::new(
            "near",
            config.near,
            "a finite distance > 0",
        ));
    }
    if config.far.is_nan() || config.far <= config.near {
        return Err(ConfigError::new(
            "far",
            config.far,
            format!("greater than near ({})", config.near),
        ));
    }
    Ok(())
}

pub(super) fn validate_frames_in_flight(config: &RenderConfig) -> Result<(), ConfigError> {
    let n = config.frames_in_flight;
    if !(1..=super::config::MAX_FRAMES_IN_FLIGHT).contains(&n) {
        return Err(ConfigError::new(
            "frames_in_flight",
            n,
            format!("1 to {}", super::config::MAX_FRAMES_IN_FLIGHT),
        ));
    }
    Ok(())
}

pub(super) fn validate_spare_instances(config: &RenderConfig) -> Result<(), ConfigError> {
    let n = config.spare_instances;
    if n > super::config::MAX_SPARE_INSTANCES {
        return Err(ConfigError::new(
            "spare_instances",
            n,
            format!("at most {} per mesh", super::config::MAX_SPARE_INSTANCES),
        ));
    }
    if n > 0 && !config.moving_instances {
        return Err(ConfigError::new(
            "spare_instances",
            n,
            "0 unless moving_instances is on (instances are added into each frame slot's own \
             buffer)",
        ));
    }
    Ok(())
}

pub(super) fn validate_culling(config: &RenderConfig) -> Result<(), ConfigError> {
    match config.culling {
        Some(c) if !(c.draw_distance.is_finite() && c.draw_distance > config.near) => {
            Err(ConfigError::new(
                "draw distance",
                c.draw_distance,
                format!("a finite distance beyond near ({})", config.near),
            ))
        }
        // The cones drop what the lens hides; without the mask those pixels would show the
        // scene minus the culled objects, an error no lens-region score would see.
        Some(c) if c.strategy.culls_to_lens() && !config.hmd_mask => Err(ConfigError::new(
            "culling",
            c.strategy.name(),
            "lens-region culling needs the HMD mask on (hmd_mask, --hmd-mask): it drops what only the mask hides",
        )),
        // The cones follow the fitted ellipse, which a runtime's mesh need not contain.
        Some(c) if c.strategy.culls_to_lens() && config.hidden_area_mesh => Err(ConfigError::new(
            "culling",
            c.strategy.name(),
            "lens-region culling follows the fitted ellipse, and the runtime's hidden-area mesh may show more: use another strategy",
        )),
        _ if config.hidden_area_mesh && !config.hmd_mask => Err(ConfigError::new(
            "hidden_area_mesh",
            true,
            "the runtime's mesh shapes the HMD mask: turn hmd_mask on",
        )),
        _ => Ok(()),
    }
}

pub(super) fn validate_features(
    config: &RenderConfig,
    caps: &DeviceCaps,
) -> Result<(), ConfigError> {
    let need = |ok: bool, field, value: &str, what: &str| {
        if ok {
            Ok(())
        } else {
            Err(ConfigError::new(
                field,
                value,
                format!("needs {what}, which {} lacks", caps.device_name),
            ))
        }
    };
    match config.stereo {
        StereoMode::Multiview => need(
            caps.max_multiview_views >= 2,
            "stereo",
            "multiview",
            "VK_KHR_multiview",
        )?,
        StereoMode::Instanced => need(
            caps.shader_clip_distance,
            "stereo",
            "instanced",
            "shaderClipDistance",
        )?,
        _ => {}
    }
    if config.count_fragments {
        need(
            caps.fragment_stores_and_atomics,
            "count_fragments",
            "true",
            "fragmentStoresAndAtomics",
        )?;
    }
    if config.timestamps {
        need(
            caps.timestamps,
            "timestamps",
            "true",
            "timestamp queries on the graphics queue",
        )?;
    }
    if config.radial_density.is_some()
        && (config.stereo != StereoMode::Multiview
            || config.foveation.is_some()
            || config.mffr.is_some())
    {
        return Err(ConfigError::new(
            "radial_density",
            "on",
            "radial density masking reconstructs a multiview stereo frame: not with another stereo mode, foveation or MFFR",
        ));
    }
    if config.mffr.is_some()
        && !matches!(config.stereo, StereoMode::Multiview | StereoMode::TwoPass)
    {
        return Err(ConfigError::new(
            "stereo",
            config.stereo,
            "MFFR composites the far field into multiview or two-pass eye passes",
        ));
    }
    if config.coverage_probe && (config.stereo != StereoMode::Multiview || !config.count_fragments)
    {
        return Err(ConfigError::new(
            "coverage_probe",
            "true",
            "needs multiview and fragment counting",
        ));
    }
    Ok(())
}

/// Stencil masks need depth-stencil attachments in a format the device may lack
/// ([`DeviceCaps::depth_stencil`]); a plan without them does not.
pub(super) fn check_depth_stencil(
    plan: &FramePlan,
    config: &RenderConfig,
    caps: &DeviceCaps,
) -> Result<(), ConfigError> {
    let stencil = plan.attachments.iter().any(|a| a.format == Format::D32S8);
    if caps.depth_stencil || !stencil {
        return Ok(());
    }
    let (field, value) = match (config.hmd_mask, config.foveation.is_some()) {
        (true, _) => ("hmd_mask", "true"),
        (false, true) => ("foveation", "its stencil masks"),
        (false, false) => ("stencil", "a stencil mask"),
    };
    Err(ConfigError::new(
        field,
        value,
        format!(
            "needs D32_SFLOAT_S8_UINT depth-stencil attachments (stencil masks), which {} lacks",
            caps.device_name
        ),
    ))
}
