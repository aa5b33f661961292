//! CPU cost of a stereo frame: recording its command buffer plus the `vkQueueSubmit` call, per
//! stereo mode and MSAA setting, side by side in one run. The GPU wait is excluded (each frame
//! is still waited for, outside the measured time). Run: `cargo bench -p foveate --bench record`.

use std::time::Duration;

use criterion::{criterion_group, criterion_main, Criterion};
use foveate::cull::Strategy;
use foveate::gpu::{Gpu, GpuOptions};
use foveate::plan::{CullConfig, RenderConfig, Resolution, StereoMode};
use foveate::render::Renderer;
use foveate::scene::{default_scene, rail_pose, ThesisScene};

fn record_and_submit(c: &mut Criterion) {
    let gpu = Gpu::new(&GpuOptions::from_env()).expect("a Vulkan device (see README)");
    let scene = default_scene();
    let mut group = c.benchmark_group("record+submit");
    group
        .sample_size(10)
        .warm_up_time(Duration::from_millis(200))
        .measurement_time(Duration::from_secs(1));
    for msaa in [1, 4] {
        for stereo in StereoMode::ALL {
            let config = RenderConfig {
                stereo,
                msaa,
                resolution: Some(Resolution::square(256)),
                count_fragments: false,
                timestamps: false,
                ..RenderConfig::default()
            };
            let plan = foveate::plan(&scene, &config, gpu.caps()).expect("valid config");
            let mut renderer = Renderer::new(&gpu, &plan, &scene).expect("renderer");
            group.bench_function(format!("{stereo}/msaa{msaa}"), |b| {
                b.iter_custom(|iters| {
                    (0..iters)
                        .map(|_| {
                            let s = renderer.render_frame(scene.head).expect("frame");
                            Duration::from_secs_f64((s.cpu_record_ms + s.cpu_submit_ms) / 1e3)
                        })
                        .sum()
                })
            });
        }
    }
    group.finish();
}

/// The CPU side of a `foveate bench` frame on the thesis scene (scale 0.05, along the rails):
/// culling, recording and submission, for the thesis' culling and submission choices.
fn thesis_frame_cpu(c: &mut Criterion) {
    let gpu = Gpu::new(&GpuOptions::from_env()).expect("a Vulkan device (see README)");
    let thesis = ThesisScene::new(0.05).expect("valid scale");
    let scene = thesis.to_scene();
    let mut group = c.benchmark_group("thesis cull+record+submit");
    group
        .sample_size(10)
        .warm_up_time(Duration::from_millis(200))
        .measurement_time(Duration::from_secs(2));
    for stereo in [StereoMode::TwoPass, StereoMode::Multiview] {
        for strategy in [Strategy::PerEye, Strategy::Superfrustum] {
            let config = RenderConfig {
                stereo,
                resolution: Some(Resolution::square(64)),
                count_fragments: false,
                timestamps: false,
                culling: Some(CullConfig {
                    strategy,
                    ..CullConfig::THESIS
                }),
                ..RenderConfig::default()
            };
            let plan = foveate::plan(&scene, &config, gpu.caps()).expect("valid config");
            let mut renderer = Renderer::new(&gpu, &plan, &scene).expect("renderer");
            let mut frame = 0;
            group.bench_function(format!("{stereo}/{}", strategy.name()), |b| {
                b.iter_custom(|iters| {
                    (0..iters)
                        .map(|_| {
                            frame += 97;
                            let pose = rail_pose(frame, thesis.extent());
                            let s = renderer.render_frame(pose).expect("frame");
                            Duration::from_secs_f64(
                                (s.cpu_cull_ms + s.cpu_record_ms + s.cpu_submit_ms) / 1e3,
                            )
                        })
                        .sum()
                })
            });
        }
    }
    group.finish();
}

criterion_group!(benches, record_and_submit, thesis_frame_cpu);
criterion_main!(benches);
