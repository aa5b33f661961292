//! A switched-off effect costs nothing: it adds no pass, attachment or buffer to the plan, no
//! Vulkan object of any kind (images, buffers, pipelines, query pools, lazily allocated
//! memory, …, counted as the renderer creates them) and not one byte of allocator memory;
//! switched on, each adds what it needs.

use std::collections::BTreeMap;

use foveate::cull::Strategy;
use foveate::foveation::FoveationConfig;
use foveate::gpu::Gpu;
use foveate::mffr::{MffrConfig, SplitDistance};
use foveate::plan::{CullConfig, FramePlan, RenderConfig, Resolution};
use foveate::render::Renderer;
use foveate::scene::{default_scene, Scene};
use foveate_tests::{assert_validation_clean, gpu};

/// What a renderer for `plan` costs: allocator bytes, live Vulkan objects by kind (after its
/// first frame), and that frame's draw calls.
struct Cost {
    bytes: u64,
    objects: BTreeMap<&'static str, i64>,
    draws: u64,
}

fn cost(gpu: &Gpu, scene: &Scene, plan: &FramePlan) -> Cost {
    let (bytes_before, objects_before) = (gpu.allocated_bytes(), gpu.live_objects());
    let mut renderer = Renderer::new(gpu, plan, scene).unwrap();
    let bytes = gpu.allocated_bytes() - bytes_before;
    let draws = renderer.render_frame(scene.head).unwrap().draw_calls;
    let objects = difference(&gpu.live_objects(), &objects_before);
    drop(renderer);
    assert_eq!(
        gpu.allocated_bytes(),
        bytes_before,
        "every byte is given back"
    );
    assert_eq!(
        gpu.live_objects(),
        objects_before,
        "every object is destroyed"
    );
    Cost {
        bytes,
        objects,
        draws,
    }
}

/// `a − b` per kind, kinds with no difference left out.
fn difference(
    a: &BTreeMap<&'static str, i64>,
    b: &BTreeMap<&'static str, i64>,
) -> BTreeMap<&'static str, i64> {
    a.keys()
        .chain(b.keys())
        .map(|&k| (k, a.get(k).unwrap_or(&0) - b.get(k).unwrap_or(&0)))
        .filter(|&(_, d)| d != 0)
        .collect()
}

fn baseline() -> RenderConfig {
    RenderConfig {
        resolution: Some(Resolution::square(64)),
        timestamps: false,
        ..RenderConfig::default()
    }
}

/// Each effect's "off" — the flag off, or configured in a way that leaves nothing to do —
/// plans exactly the baseline and creates exactly its objects and bytes. Mutation: a pipeline,
/// buffer or image created whether or not its effect is planned (say the mask pipeline or the
/// counter buffer made unconditionally) fails it.
#[test]
fn switched_off_effects_cost_no_object_and_no_byte() {
    let gpu = gpu();
    let scene = default_scene();
    let empty = Scene::empty();
    let plan = |s: &Scene, c: &RenderConfig| foveate::plan(s, c, gpu.caps()).unwrap();
    for (scene, what) in [(&scene, "default scene"), (&empty, "empty scene")] {
        let base_plan = plan(scene, &baseline());
        assert!(base_plan.buffers.is_empty() && base_plan.timestamp_queries == 0);
        assert!(base_plan.counted.is_empty());
        let base = cost(&gpu, scene, &base_plan);
        assert!(base.objects["Pipeline"] >= 1 && base.objects["Image"] >= 1);
        let mut offs = vec![
            (
                "MFFR split past the far plane",
                RenderConfig {
                    mffr: Some(MffrConfig {
                        split: SplitDistance::Metres(baseline().far * 2.0),
                        ..MffrConfig::default()
                    }),
                    ..baseline()
                },
            ),
            ("every flag off", baseline()),
        ];
        if what == "empty scene" {
            // Nothing beyond the split: MFFR has no far field to render.
            offs.push((
                "MFFR without far content",
                RenderConfig {
                    mffr: Some(MffrConfig::default()),
                    ..baseline()
                },
            ));
        }
        for (name, config) in offs {
            let p = plan(scene, &config);
            assert_eq!(p, base_plan, "{what}, {name}: the baseline's plan");
            let c = cost(&gpu, scene, &p);
            assert_eq!(c.objects, base.objects, "{what}, {name}: objects");
            assert_eq!(
                (c.bytes, c.draws),
                (base.bytes, base.draws),
                "{what}, {name}"
            );
        }
    }
    assert_validation_clean(&gpu);
}

/// Switched on, each effect adds the objects it needs and the plan shows them — and the
/// instruments add exactly their objects: the counter buffer (its shader variants replace the
/// plain ones) with the pipeline-statistics query pool, or the timestamp query pool. Mutation: an effect whose resources are not created,
/// or counting that leaves an extra pipeline behind, fails it.
#[test]
fn switched_on_effects_add_what_they_need() {
    let gpu = gpu();
    let scene = default_scene();
    let plan = |c: &RenderConfig| foveate::plan(&scene, c, gpu.caps()).unwrap();
    let base_plan = plan(&baseline());
    let base = cost(&gpu, &scene, &base_plan);
    let on = |f: &dyn Fn(&mut RenderConfig)| {
        let mut c = baseline();
        f(&mut c);
        c
    };
    let mut cases: Vec<(String, RenderConfig)> = vec![
        ("hmd mask".into(), on(&|c| c.hmd_mask = true)),
        ("mffr".into(), on(&|c| c.mffr = Some(MffrConfig::default()))),
        (
            "foveation".into(),
            on(&|c| {
                c.foveation = Some(FoveationConfig::single_frame());
            }),
        ),
        (
            "fragment counting".into(),
            on(&|c| c.count_fragments = true),
        ),
        ("timestamps".into(), on(&|c| c.timestamps = true)),
        (
            "lens output".into(),
            on(&|c| c.output = foveate::plan::OutputStage::Lens),
        ),
    ];
    for strategy in Strategy::ALL {
        cases.push((
            format!("culling {}", strategy.name()),
            on(&|c| {
                c.hmd_mask = strategy.culls_to_lens();
                c.culling = Some(CullConfig {
                    strategy,
                    draw_distance: 100.0,
                });
            }),
        ));
    }
    for (name, config) in cases {
        let p = plan(&config);
        assert_ne!(p, base_plan, "{name} changes the plan");
        let c = cost(&gpu, &scene, &p);
        let added = difference(&c.objects, &base.objects);
        let slots = i64::from(p.frame_slots);
        match name.as_str() {
            // The counter buffer, and the pipeline-statistics queries where the device has them.
            // One of each per frame slot.
            "fragment counting" => assert_eq!(
                added,
                if gpu.caps().pipeline_statistics {
                    BTreeMap::from([("Buffer", slots), ("QueryPool", slots)])
                } else {
                    BTreeMap::from([("Buffer", slots)])
                },
                "{name}"
            ),
            "timestamps" => assert_eq!(added, BTreeMap::from([("QueryPool", slots)]), "{name}"),
            _ => assert!(
                added.values().any(|&n| n > 0),
                "{name} adds no object: {added:?}"
            ),
        }
        match name.as_str() {
            // Smaller views replace the full-size ones: foveation changes the bytes, downwards.
            "foveation" => assert_ne!(c.bytes, base.bytes),
            "timestamps" => assert_eq!(c.bytes, base.bytes, "a query pool is no allocation"),
            _ => assert!(
                c.bytes > base.bytes,
                "{name}: {} vs {}",
                c.bytes,
                base.bytes
            ),
        }
    }
    assert_validation_clean(&gpu);
}

/// Lit shading is an effect of the scene: a lit scene's renderer makes its three texture
/// arrays, sampler, material and light buffers; the same scene flat makes none of them.
/// Mutation: textures made for a flat scene fail it.
#[test]
fn lit_shading_adds_its_textures_and_flat_none() {
    let gpu = gpu();
    let lit = default_scene().with_shading(foveate::scene::Shading::Lit);
    let flat = default_scene();
    let plan = |s: &Scene| foveate::plan(s, &baseline(), gpu.caps()).unwrap();
    let (lit_plan, flat_plan) = (plan(&lit), plan(&flat));
    assert!(lit_plan.lit && !flat_plan.lit);
    let added = difference(
        &cost(&gpu, &lit, &lit_plan).objects,
        &cost(&gpu, &flat, &flat_plan).objects,
    );
    assert_eq!(
        (added.get("Image"), added.get("Sampler")),
        (Some(&3), Some(&1)),
        "{added:?}"
    );
    assert_eq!(
        added.get("Buffer"),
        Some(&2),
        "materials and lights: {added:?}"
    );
    assert_validation_clean(&gpu);
}
