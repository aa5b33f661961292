//! An engine's scene passes one view at a time, on a driver that misplaces the primitives a
//! multiview pass clips ([`DriverQuirks::multiview_clipping_drops_views`](super::DriverQuirks)).
//!
//! foveate's own scenes stay multiview there: a guard band keeps primitives off the viewport's
//! edges and its meshes are built so that none crosses an eye's plane. An engine's triangles
//! can (a ground plane under the viewer), and such a triangle must be clipped; in a multiview
//! pass the driver then draws it into the first view only. So each scene pass of an engine's
//! plan becomes one pass per view, each rendering one layer of the same images as a multiview
//! pass of that one view: `gl_ViewIndex` is 0, the pass's first view is the view, and an engine
//! that indexes its views by `DrawPass::views.start + gl_ViewIndex` (as the guide says) draws
//! the same frame, pass by pass.
//!
//! Where the same driver resolves into layer 0 whatever the target's base layer
//! ([`DriverQuirks::layered_resolve_ignores_base_layer`](super::DriverQuirks)), a view past
//! the first resolves into an image of its own, and a pass after it copies that image into its
//! layer (`shaders/layer_copy.frag`). The cost, on such drivers only: a render pass per view
//! instead of per pair (the engine records its draws once per view, a tile GPU loads its
//! tiles once per view), and a multisampled view's resolve stored and read once more.

use super::attachments::{AttachmentPlan, Use};
use super::model::{PassKind, PassPlan, Submission};
use super::ops::{Access, AttachmentId};
use super::pipeline::{PipelineDesc, StepContext};
use super::steps::Step;
use super::ConfigError;
use crate::shaders::{COMPOSITE_VERT, LAYER_COPY_FRAG, LAYER_COPY_FRAG_COUNTING};
use crate::view::Eye;

/// Each multiview scene pass of `passes` as one pass per view, in view order; with
/// `resolve_lands_in_layer_0`, a view past the first that resolves does so into an image of
/// its own (added to `attachments`), copied into its layer by the pass that follows it.
pub(super) fn one_pass_per_view(
    passes: Vec<PassPlan>,
    attachments: &mut Vec<AttachmentPlan>,
    resolve_lands_in_layer_0: bool,
) -> Result<Vec<PassPlan>, ConfigError> {
    let mut out = Vec::with_capacity(passes.len() * 2);
    for pass in passes {
        let views = pass.view_mask.count_ones();
        let scene = pass.steps.iter().any(|s| matches!(s, Step::Scene { .. }));
        if views < 2 || !scene {
            out.push(pass);
            continue;
        }
        debug_assert_eq!(pass.view_mask, (1 << views) - 1, "views from layer 0");
        for view in 0..views {
            let narrow = |u: Use| Use {
                base_layer: u.base_layer + view,
                layer_count: 1,
                ..u
            };
            let mut one = PassPlan {
                name: view_pass_name(pass.name, view),
                view_mask: 0b1,
                color: narrow(pass.color),
                depth: pass.depth.map(narrow),
                resolve: pass.resolve.map(narrow),
                depth_resolve: pass.depth_resolve.map(narrow),
                history: pass.history.map(narrow),
                first_view: pass.first_view + view,
                ..pass.clone()
            };
            let copy = match one.resolve {
                Some(target) if resolve_lands_in_layer_0 && target.base_layer > 0 => {
                    check_no_depth_resolve(&one)?;
                    Some(resolve_alone(&mut one, target, attachments))
                }
                _ => None,
            };
            out.push(one);
            out.extend(copy);
        }
    }
    Ok(out)
}

/// Points `pass`'s resolve at an image of its own, of one layer, and returns the pass that
/// copies it into `target`'s layer.
fn resolve_alone(
    pass: &mut PassPlan,
    target: Use,
    attachments: &mut Vec<AttachmentPlan>,
) -> PassPlan {
    let [alone, copy_name] = resolved_alone_names(pass.name);
    attachments.push(AttachmentPlan {
        name: alone,
        layers: 1,
        ..attachments[target.attachment].clone()
    });
    let resolved: AttachmentId = attachments.len() - 1;
    pass.resolve = Some(Use::new(resolved, 0, 1, Access::Overwrite));
    // The driver resolves from the multisampled image's layer 0 too: render there (it is
    // cleared by every pass that uses it, and kept by none).
    pass.color.base_layer = 0;
    PassPlan {
        samples: vec![resolved],
        steps: vec![Step::LayerCopy { from: resolved }],
        first_view: pass.first_view,
        ..PassPlan::new(
            copy_name,
            PassKind::LayerCopy,
            0,
            Submission::SingleEye(Eye::BOTH[pass.first_view as usize % 2]),
            Use::new(target.attachment, target.base_layer, 1, Access::Overwrite),
        )
    }
}

/// A multisampled periphery that accumulates resolves its depth too, which a colour copy
/// cannot put in place.
fn check_no_depth_resolve(pass: &PassPlan) -> Result<(), ConfigError> {
    match pass.depth_resolve {
        Some(_) => Err(ConfigError::new(
            "foveation.periphery_msaa",
            "a multisampled periphery accumulated over frames, for an engine's draws",
            "one sample on this driver: it draws an engine's views one pass each, and cannot \
             resolve depth into the right eye's layer",
        )),
        None => Ok(()),
    }
}

/// The name of view `view`'s pass of the multiview pass `name`.
fn view_pass_name(name: &'static str, view: u32) -> &'static str {
    const EYES: [&str; 2] = ["scene (left eye)", "scene (right eye)"];
    const PERIPHERY: [&str; 2] = ["scene (left periphery)", "scene (right periphery)"];
    const FOVEA: [&str; 2] = ["scene (left fovea)", "scene (right fovea)"];
    let view = view as usize;
    match name {
        "scene (multiview)" => EYES[view],
        "scene (periphery views)" => PERIPHERY[view],
        "scene (fovea views)" => FOVEA[view],
        "scene (foveated multiview)" => [PERIPHERY, FOVEA].concat()[view],
        _ => name,
    }
}

/// The image a view's pass resolves into alone, and the pass copying it into its layer.
fn resolved_alone_names(pass: &'static str) -> [&'static str; 2] {
    match pass {
        "scene (right eye)" => [
            "right eye (resolved alone)",
            "copy (right eye into its layer)",
        ],
        "scene (right periphery)" => [
            "right periphery (resolved alone)",
            "copy (right periphery into its layer)",
        ],
        "scene (left fovea)" => [
            "left fovea (resolved alone)",
            "copy (left fovea into its layer)",
        ],
        "scene (right fovea)" => [
            "right fovea (resolved alone)",
            "copy (right fovea into its layer)",
        ],
        _ => ["a view (resolved alone)", "copy (a view into its layer)"],
    }
}

/// The copy: a full-view triangle fetching the resolved image texel by texel.
pub(super) fn layer_copy_pipeline(ctx: &StepContext) -> PipelineDesc {
    ctx.pipeline(&COMPOSITE_VERT, &LAYER_COPY_FRAG, &LAYER_COPY_FRAG_COUNTING)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::foveation::FoveationConfig;
    use crate::plan::{plan_for_engine, DeviceCaps, LoadOp, RenderConfig, StoreOp};

    fn engine_plan(clipping: bool, resolve: bool) -> Result<crate::plan::FramePlan, ConfigError> {
        let mut caps = DeviceCaps::generic();
        caps.quirks.multiview_clipping_drops_views = clipping;
        caps.quirks.layered_resolve_ignores_base_layer = resolve;
        let config = RenderConfig {
            foveation: Some(FoveationConfig::default()),
            ..RenderConfig::default()
        };
        plan_for_engine(&config, &caps)
    }

    fn names(plan: &crate::plan::FramePlan) -> Vec<&str> {
        plan.passes.iter().map(|p| p.name).collect()
    }

    /// Where the driver misplaces clipped multiview primitives, an engine's scene passes draw
    /// one view each, into their view's layer; elsewhere, and for foveate's own scene, they
    /// stay multiview. Mutation: the split left out, or the layers not narrowed, fails it.
    #[test]
    fn an_engines_scene_passes_draw_one_view_each_where_clipping_misplaces() {
        let multiview = engine_plan(false, false).unwrap();
        assert_eq!(
            names(&multiview)[..2],
            ["scene (periphery views)", "scene (fovea views)"]
        );
        let split = engine_plan(true, false).unwrap();
        let scene: Vec<&PassPlan> = (split.passes.iter())
            .filter(|p| p.kind == PassKind::Scene)
            .collect();
        let expected = [
            "scene (left periphery)",
            "scene (right periphery)",
            "scene (left fovea)",
            "scene (right fovea)",
        ];
        assert_eq!(scene.iter().map(|p| p.name).collect::<Vec<_>>(), expected);
        for (view, pass) in scene.iter().enumerate() {
            assert_eq!((pass.view_mask, pass.first_view), (0b1, view as u32));
            let layer = view as u32 % 2;
            for u in [Some(pass.color), pass.depth, pass.resolve]
                .into_iter()
                .flatten()
            {
                assert_eq!((u.base_layer, u.layer_count), (layer, 1), "{}", pass.name);
            }
        }
        let own = crate::plan(
            &crate::scene::default_scene(),
            &RenderConfig {
                foveation: Some(FoveationConfig::default()),
                ..RenderConfig::default()
            },
            &{
                let mut caps = DeviceCaps::generic();
                caps.quirks.multiview_clipping_drops_views = true;
                caps
            },
        )
        .unwrap();
        assert!(
            names(&own).contains(&"scene (fovea views)"),
            "{:?}",
            names(&own)
        );
    }

    /// Where the driver's resolve also lands in layer 0, the right fovea resolves alone (from
    /// the multisampled image's layer 0) and a copy pass puts it in its layer: the image is
    /// stored and sampled, the copy overwrites that one layer. Mutation: the copy pass left
    /// out, or the resolve left in layer 1, fails it.
    #[test]
    fn a_resolve_that_cannot_land_in_its_layer_is_copied_there() {
        let plan = engine_plan(true, true).unwrap();
        let at = |name: &str| plan.passes.iter().position(|p| p.name == name).unwrap();
        let right = &plan.passes[at("scene (right fovea)")];
        let copy = &plan.passes[at("scene (right fovea)") + 1];
        assert_eq!(copy.name, "copy (right fovea into its layer)");
        let resolve = right.resolve.unwrap();
        let alone = &plan.attachments[resolve.attachment];
        assert_eq!(
            (alone.name, alone.layers),
            ("right fovea (resolved alone)", 1)
        );
        assert_eq!((resolve.base_layer, right.color.base_layer), (0, 0));
        assert_eq!(resolve.store, StoreOp::Store);
        assert!(alone.sampled && !alone.transient);
        assert_eq!(copy.samples, vec![resolve.attachment]);
        assert_eq!(
            copy.steps,
            vec![Step::LayerCopy {
                from: resolve.attachment
            }]
        );
        let left = plan.passes[at("scene (left fovea)")].resolve.unwrap();
        assert_eq!(copy.color.attachment, left.attachment, "the fovea views");
        assert_eq!((copy.color.base_layer, copy.color.layer_count), (1, 1));
        assert_eq!(copy.color.load, LoadOp::DontCare);
        let printed = plan.to_string();
        assert!(
            printed.contains("copying the image it samples"),
            "{printed}"
        );
        // Only views past the first of their image are copied.
        assert_eq!(
            plan.passes
                .iter()
                .filter(|p| p.kind == PassKind::LayerCopy)
                .count(),
            1
        );
        // The output pass waits for the copy's layer, as for any colour attachment.
        let output = plan.passes.last().unwrap();
        let waits = &output.barriers.wait;
        assert!(
            waits.iter().any(|b| b.attachment == copy.color.attachment),
            "{waits:?}"
        );
    }

    /// A multisampled periphery that accumulates also resolves its depth, which no colour copy
    /// puts in place: refused by name on such a driver.
    #[test]
    fn a_depth_resolve_that_cannot_land_in_its_layer_is_refused() {
        let mut caps = DeviceCaps::generic();
        caps.quirks.multiview_clipping_drops_views = true;
        caps.quirks.layered_resolve_ignores_base_layer = true;
        let config = RenderConfig {
            foveation: Some(FoveationConfig {
                periphery_msaa: Some(4),
                ..FoveationConfig::default()
            }),
            ..RenderConfig::default()
        };
        let error = plan_for_engine(&config, &caps).unwrap_err();
        assert_eq!(error.field, "foveation.periphery_msaa", "{error}");
    }
}
