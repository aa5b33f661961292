//! Planning a frame an engine draws: foveate places the views, masks them and composes the
//! output; the scene steps are the engine's own draws. What only foveate's own scene can do —
//! its culling, levels of detail, moving instances, MFFR's near and far sets, radial density's
//! reconstruction, the coverage probe, the submission strategies other than multiview — is
//! refused, naming the field.

use super::build::plan_with;
use super::{ConfigError, DeviceCaps, FramePlan, RenderConfig, StereoMode};
use crate::scene::Scene;

/// Plans a frame whose scene steps an engine draws with its own pipelines (the plan's
/// [`FramePlan::engine_draws`]): the views, the stencil masks, the output stage, the images and
/// the barriers, as [`crate::plan()`] plans them for foveate's scene. Rejects what needs
/// foveate's scene with an error naming the field, the value and the limit.
pub fn plan_for_engine(config: &RenderConfig, caps: &DeviceCaps) -> Result<FramePlan, ConfigError> {
    refuse_scene_features(config)?;
    plan_with(&Scene::empty(), true, config, caps)
}

/// The configuration asks for nothing only foveate's scene renderer has.
fn refuse_scene_features(config: &RenderConfig) -> Result<(), ConfigError> {
    let scene_only = |field: &'static str, value: String| {
        Err(ConfigError::new(
            field,
            value,
            "off for an engine's draws: it is foveate's own scene renderer's (foveate::plan and Renderer)",
        ))
    };
    if config.stereo != StereoMode::Multiview {
        return Err(ConfigError::new(
            "stereo",
            config.stereo,
            "multiview for an engine's draws: each view a layer of the pass the engine draws into",
        ));
    }
    if let Some(c) = config.culling {
        return scene_only("culling", format!("{c:?}"));
    }
    if let Some(l) = config.lod {
        return scene_only("lod", format!("{} px", l.max_error_px));
    }
    if config.moving_instances {
        return scene_only("moving_instances", "true".into());
    }
    if config.foveation.is_some_and(|f| f.periphery_prefilter) {
        return scene_only("periphery_prefilter", "true".into());
    }
    if let Some(r) = config.foveation.and_then(|f| f.ring_ratio) {
        return scene_only("ring_ratio", r.to_string());
    }
    if config.spare_instances > 0 {
        return scene_only("spare_instances", config.spare_instances.to_string());
    }
    if let Some(m) = config.mffr {
        return scene_only("mffr", m.name().into());
    }
    if config.radial_density.is_some() {
        return scene_only("radial_density", "on".into());
    }
    if config.coverage_probe {
        return scene_only("coverage_probe", "true".into());
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::foveation::FoveationConfig;
    use crate::plan::{FoveaLayout, Resolution, Step};

    fn foveated() -> RenderConfig {
        RenderConfig {
            resolution: Some(Resolution::square(256)),
            foveation: Some(FoveationConfig::single_frame()),
            ..RenderConfig::default()
        }
    }

    /// An engine's plan has the masks and the output stage of foveate's plan for the same
    /// configuration, and scene steps that draw no set of foveate's. Mutation: cull slots
    /// assigned for the engine (a culled fovea set) fail it.
    #[test]
    fn an_engines_plan_is_foveates_plan_without_the_scene() {
        let caps = DeviceCaps::generic();
        let config = RenderConfig {
            fovea_layout: FoveaLayout::TwoPass,
            ..foveated()
        };
        let engine = plan_for_engine(&config, &caps).unwrap();
        let own = crate::plan(&crate::scene::default_scene(), &config, &caps).unwrap();
        assert!(engine.engine_draws && !own.engine_draws);
        assert_eq!(engine.passes.len(), own.passes.len());
        for (e, o) in engine.passes.iter().zip(&own.passes) {
            assert_eq!((e.name, e.view_mask, e.kind), (o.name, o.view_mask, o.kind));
            assert_eq!(e.has_masks(), o.has_masks(), "{}", e.name);
        }
        assert!(engine.cull_slots.is_empty() && engine.instance_ids().is_none());
        let scene_steps = engine.passes.iter().flat_map(|p| &p.steps);
        for step in scene_steps {
            if let Step::Scene { cull_slot, .. } = step {
                assert_eq!(*cull_slot, None);
            }
        }
    }

    /// An engine's frame with the periphery accumulated reads alpha 0 as a surface that moved
    /// on its own (the engine marks its own), as foveate's moving instances are read; foveate's
    /// plan of a still scene does not. Mutation: `marks_moving` without the engine's case
    /// fails it.
    #[test]
    fn an_engines_moving_surfaces_are_read_from_alpha() {
        let caps = DeviceCaps::generic();
        let config = RenderConfig {
            foveation: Some(FoveationConfig {
                periphery_temporal: Some(Default::default()),
                ..FoveationConfig::single_frame()
            }),
            ..foveated()
        };
        let marks = |plan: &FramePlan| {
            let output = plan.passes.last().unwrap();
            (output.pipelines[0].constants).contains(&(crate::plan::Constant::MarkMoving, 1))
        };
        assert!(marks(&plan_for_engine(&config, &caps).unwrap()));
        let scene = crate::scene::default_scene();
        assert!(!marks(&crate::plan(&scene, &config, &caps).unwrap()));
    }

    /// Each of foveate's own scene features is refused by name. Mutation: dropping a check
    /// lets its configuration plan.
    #[test]
    fn what_only_foveates_scene_has_is_refused_by_name() {
        let caps = DeviceCaps::generic();
        let cases: [(&str, RenderConfig); 7] = [
            (
                "stereo",
                RenderConfig {
                    stereo: StereoMode::TwoPass,
                    ..foveated()
                },
            ),
            (
                "culling",
                RenderConfig {
                    culling: Some(crate::plan::CullConfig::THESIS),
                    ..foveated()
                },
            ),
            (
                "moving_instances",
                RenderConfig {
                    moving_instances: true,
                    ..foveated()
                },
            ),
            (
                "spare_instances",
                RenderConfig {
                    spare_instances: 2,
                    ..foveated()
                },
            ),
            (
                "mffr",
                RenderConfig {
                    mffr: Some(Default::default()),
                    ..RenderConfig::default()
                },
            ),
            (
                "coverage_probe",
                RenderConfig {
                    coverage_probe: true,
                    ..foveated()
                },
            ),
            (
                "radial_density",
                RenderConfig {
                    radial_density: Some(Default::default()),
                    ..RenderConfig::default()
                },
            ),
        ];
        for (field, config) in cases {
            let err = plan_for_engine(&config, &caps).unwrap_err();
            assert!(err.to_string().contains(field), "{field}: {err}");
        }
        assert!(plan_for_engine(&foveated(), &caps).is_ok());
    }
}
