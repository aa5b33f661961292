//! A switched-off effect costs nothing: it adds no pass, attachment or buffer to the plan and
//! not one byte to what the renderer allocates (measured from the allocator); switched on, it
//! does add them.

use foveate::cull::Strategy;
use foveate::foveation::FoveationConfig;
use foveate::gpu::Gpu;
use foveate::mffr::{MffrConfig, SplitDistance};
use foveate::plan::{CullConfig, FramePlan, RenderConfig, Resolution};
use foveate::render::Renderer;
use foveate::scene::{default_scene, Scene};
use foveate_tests::{assert_validation_clean, gpu};

/// Bytes a renderer for `plan` allocates, and the draw calls of its first frame.
fn cost(gpu: &Gpu, scene: &Scene, plan: &FramePlan) -> (u64, u64) {
    let before = gpu.allocated_bytes();
    let mut renderer = Renderer::new(gpu, plan, scene).unwrap();
    let bytes = gpu.allocated_bytes() - before;
    let draws = renderer.render_frame(scene.head).unwrap().draw_calls;
    drop(renderer);
    assert_eq!(gpu.allocated_bytes(), before, "everything is given back");
    (bytes, draws)
}

#[test]
fn switched_off_effects_are_absent_from_plan_and_allocation() {
    let gpu = gpu();
    let scene = default_scene();
    let baseline = RenderConfig {
        resolution: Some(Resolution::square(64)),
        count_fragments: false,
        timestamps: false,
        ..RenderConfig::default()
    };
    let plan = |c: &RenderConfig| foveate::plan(&scene, c, gpu.caps()).unwrap();
    let base_plan = plan(&baseline);
    assert!(base_plan.buffers.is_empty() && base_plan.timestamp_queries == 0);
    let (base_bytes, base_draws) = cost(&gpu, &scene, &base_plan);

    // Configured but switched off: the plan is the baseline's, and so is the allocation.
    let split_past_far = RenderConfig {
        mffr: Some(MffrConfig {
            split: SplitDistance::Metres(baseline.far * 2.0),
            ..MffrConfig::default()
        }),
        ..baseline.clone()
    };
    let off = plan(&split_past_far);
    assert_eq!(off, base_plan);
    assert_eq!(cost(&gpu, &scene, &off), (base_bytes, base_draws));

    let on: [(&str, RenderConfig); 6] = [
        (
            "hmd mask",
            RenderConfig {
                hmd_mask: true,
                ..baseline.clone()
            },
        ),
        (
            "mffr",
            RenderConfig {
                mffr: Some(MffrConfig::default()),
                ..baseline.clone()
            },
        ),
        (
            "foveation",
            RenderConfig {
                foveation: Some(FoveationConfig::default()),
                views: 4,
                ..baseline.clone()
            },
        ),
        (
            "culling",
            RenderConfig {
                culling: Some(CullConfig {
                    strategy: Strategy::Superfrustum,
                    draw_distance: 100.0,
                }),
                ..baseline.clone()
            },
        ),
        (
            "fragment counter",
            RenderConfig {
                count_fragments: true,
                ..baseline.clone()
            },
        ),
        (
            "timestamps",
            RenderConfig {
                timestamps: true,
                ..baseline.clone()
            },
        ),
    ];
    for (name, config) in on {
        let p = plan(&config);
        assert_ne!(p, base_plan, "{name} changes the plan");
        let (bytes, _) = cost(&gpu, &scene, &p);
        match name {
            // A query pool is not allocator memory; the plan shows its queries instead.
            "timestamps" => assert!(p.timestamp_queries > 0),
            // Smaller views replace the full-size ones: foveation changes the bytes, downwards.
            "foveation" => assert_ne!(bytes, base_bytes),
            _ => assert!(bytes > base_bytes, "{name}: {bytes} vs {base_bytes}"),
        }
    }
    assert_validation_clean(&gpu);
}
