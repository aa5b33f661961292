//! An engine's own draws through a `FoveationLayer` (the `bring_your_own_draws` example's
//! engine: its own vertex layout, shaders and pipelines) against foveate's own renderer of the
//! same glTF scene, flat shaded: the frames are equal, and each thing an engine can get wrong
//! shows; and an engine's ground plane, drawn by each eye's own views on every driver.
//! Validation is on; any message fails the test.

#[path = "../examples/bring_your_own_draws/engine.rs"]
#[allow(dead_code)]
mod engine;

use std::path::Path;

use engine::{Engine, EngineVertex, World, WorldMesh, WorldObject};
use foveate::ash::vk;
use foveate::cull::Sphere;
use foveate::foveation::{FoveationConfig, TemporalConfig};
use foveate::glam::{Mat4, Vec2, Vec3, Vec4};
use foveate::gpu::{Gpu, GpuOptions, Image};
use foveate::plan::{
    plan_for_engine, DeviceCaps, FramePlan, OutputStage, PassKind, RenderConfig, Resolution,
};
use foveate::render::{
    output_image_desc, view_images, DrawPass, FoveationLayer, FrameInput, FrameViewSet,
    HandedImage, Renderer, StereoImage, View,
};
use foveate::scene::Shading;

const MODEL: &str =
    "/usr/share/assimp/models/glTF2/2CylinderEngine-glTF-Binary/2CylinderEngine.glb";

fn gpu() -> Gpu {
    let options = GpuOptions {
        validation: true,
        device: std::env::var("FOVEATE_DEVICE").ok(),
        pipeline_cache: None,
        display: None,
    };
    Gpu::new(&options).expect("a Vulkan device with VK_LAYER_KHRONOS_validation (see README)")
}

fn world() -> World {
    assert!(
        Path::new(MODEL).exists(),
        "{MODEL} is missing: install Debian's assimp-testmodels (scripts/setup.sh does)"
    );
    World::from_gltf(Path::new(MODEL)).expect("the model loads")
}

/// A foveated frame through the lens at 160² per eye, far enough for the model.
fn config(world: &World, temporal: Option<TemporalConfig>) -> RenderConfig {
    RenderConfig {
        hmd: "quest-pro".into(),
        resolution: Some(Resolution::square(160)),
        foveation: Some(FoveationConfig {
            periphery_temporal: temporal,
            ..FoveationConfig::single_frame()
        }),
        output: OutputStage::Lens,
        far: world.reach.max(RenderConfig::default().far),
        ..RenderConfig::default()
    }
}

/// The frames of a moving gaze, and a head turning a little.
fn inputs(head: Mat4, frames: usize) -> Vec<FrameInput> {
    (0..frames)
        .map(|i| {
            let t = i as f32;
            let turn = Mat4::from_rotation_y(0.01 * t) * Mat4::from_translation(Vec3::X * 0.0);
            FrameInput::new(head * turn).with_gaze([Vec2::new(-0.2 + 0.1 * t, 0.1); 2])
        })
        .collect()
}

/// foveate's own renderer's last frame of `inputs`.
fn renderer_frames(gpu: &Gpu, config: &RenderConfig, inputs: &[FrameInput]) -> StereoImage {
    let scene = foveate::scene::load_gltf(Path::new(MODEL))
        .unwrap()
        .with_shading(Shading::Flat);
    let plan = foveate::plan(&scene, config, gpu.caps()).unwrap();
    let mut renderer = Renderer::new(gpu, &plan, &scene).unwrap();
    for input in inputs {
        renderer.render(input).unwrap();
    }
    renderer.readback().unwrap()
}

/// What the engine's frames gave: the last image, and the last frame's samples that passed
/// the depth and stencil tests in each pass the engine drew (an occlusion query around its
/// draws, the test's own).
struct EngineRun {
    image: StereoImage,
    samples_passed: Vec<u64>,
}

/// The engine's last frame of `inputs` through `layer`, its pipelines made for `passes` (the
/// layer's, unless a test changes them) and each frame's views through `views` before they are
/// written.
fn engine_frames(
    gpu: &Gpu,
    mut layer: FoveationLayer,
    inputs: &[FrameInput],
    passes: &dyn Fn(Vec<DrawPass>) -> Vec<DrawPass>,
    views: &dyn Fn(&mut Vec<View>),
) -> EngineRun {
    let draw_passes = layer.draw_passes();
    let mut engine = Engine::new(gpu, world(), &passes(draw_passes.clone()), 2).unwrap();
    let occlusion = Occlusion::new(gpu, &draw_passes);
    let mut samples_passed = Vec::new();
    for input in inputs {
        let mut set = layer.views(input).unwrap();
        views(&mut set.views);
        engine.write_views(set.slot, &set.views);
        samples_passed = occlusion.frame(&mut layer, &set, &mut engine);
    }
    let image = layer.readback().unwrap();
    drop(engine);
    drop(layer);
    drop(occlusion);
    gpu.check_validation().unwrap();
    EngineRun {
        image,
        samples_passed,
    }
}

/// The test's own frame loop (raw Vulkan, as an engine's): a command buffer of its own, and an
/// occlusion query around the engine's draws in each pass (a multiview pass takes one query
/// per view; their sum is the pass's).
struct Occlusion {
    device: foveate::ash::Device,
    queue: vk::Queue,
    pool: vk::QueryPool,
    commands: vk::CommandPool,
    cmd: vk::CommandBuffer,
    fence: vk::Fence,
    /// Each pass's index, first query and views (one query each).
    queries: Vec<(usize, u32, u32)>,
    count: u32,
}

impl Occlusion {
    fn new(gpu: &Gpu, passes: &[DrawPass]) -> Self {
        let mut queries = Vec::new();
        let mut count = 0;
        for p in passes {
            let views = p.view_mask.count_ones();
            queries.push((p.index, count, views));
            count += views;
        }
        let device = gpu.device().clone();
        let raw = gpu.raw_handles();
        unsafe {
            let info = vk::QueryPoolCreateInfo::default()
                .query_type(vk::QueryType::OCCLUSION)
                .query_count(count);
            let pool = device.create_query_pool(&info, None).unwrap();
            let info = vk::CommandPoolCreateInfo::default()
                .queue_family_index(raw.queue_family)
                .flags(vk::CommandPoolCreateFlags::RESET_COMMAND_BUFFER);
            let commands = device.create_command_pool(&info, None).unwrap();
            let info = vk::CommandBufferAllocateInfo::default()
                .command_pool(commands)
                .command_buffer_count(1);
            let cmd = device.allocate_command_buffers(&info).unwrap()[0];
            let fence = device
                .create_fence(&vk::FenceCreateInfo::default(), None)
                .unwrap();
            Occlusion {
                queue: device.get_device_queue(raw.queue_family, raw.queue_index),
                device,
                pool,
                commands,
                cmd,
                fence,
                queries,
                count,
            }
        }
    }

    /// Records, submits and waits for one frame; each pass's samples passed.
    fn frame(
        &self,
        layer: &mut FoveationLayer,
        views: &FrameViewSet,
        engine: &mut Engine,
    ) -> Vec<u64> {
        let d = &self.device;
        unsafe {
            let begin = vk::CommandBufferBeginInfo::default();
            d.begin_command_buffer(self.cmd, &begin).unwrap();
            d.cmd_reset_query_pool(self.cmd, self.pool, 0, self.count);
            let mut draw = |ctx: &foveate::render::DrawContext| {
                let q = self.queries.iter().find(|q| q.0 == ctx.pass.index).unwrap();
                d.cmd_begin_query(ctx.cmd, self.pool, q.1, vk::QueryControlFlags::empty());
                engine.draw(ctx);
                d.cmd_end_query(ctx.cmd, self.pool, q.1);
            };
            layer.record(self.cmd, views, &mut draw).unwrap();
            d.end_command_buffer(self.cmd).unwrap();
            let cmds = [self.cmd];
            let submit = vk::SubmitInfo::default().command_buffers(&cmds);
            d.queue_submit(self.queue, &[submit], self.fence).unwrap();
            d.wait_for_fences(&[self.fence], true, u64::MAX).unwrap();
            d.reset_fences(&[self.fence]).unwrap();
        }
        // The first query of each pass: view 0's samples (lavapipe sums every view's there;
        // which query holds the others is the driver's choice), and what the masks cut they
        // cut in every view. Not precise (foveate enables no `occlusionQueryPrecise`): lavapipe
        // counts exactly anyway; a driver that only says "some" fails the test, never passes
        // it falsely.
        let flags = vk::QueryResultFlags::TYPE_64 | vk::QueryResultFlags::WAIT;
        (self.queries.iter())
            .map(|&(_, first, _)| {
                let mut samples = [0u64];
                unsafe { d.get_query_pool_results(self.pool, first, &mut samples, flags) }.unwrap();
                samples[0]
            })
            .collect()
    }
}

impl Drop for Occlusion {
    fn drop(&mut self) {
        unsafe {
            let d = &self.device;
            d.device_wait_idle().unwrap();
            d.destroy_fence(self.fence, None);
            d.destroy_command_pool(self.commands, None);
            d.destroy_query_pool(self.pool, None);
        }
    }
}

/// Pixels of `a` and `b` (both eyes) that differ in any channel.
fn differing(a: &StereoImage, b: &StereoImage) -> usize {
    let eyes = a.eyes().into_iter().zip(b.eyes());
    eyes.map(|(x, y)| {
        x.data
            .chunks(4)
            .zip(y.data.chunks(4))
            .filter(|(p, q)| p != q)
            .count()
    })
    .sum()
}

/// The engine's frames as it should draw them, through a layer with images of its own.
fn plain_engine_frames(gpu: &Gpu, config: &RenderConfig, inputs: &[FrameInput]) -> EngineRun {
    engine_frames(gpu, layer(gpu, config), inputs, &unchanged, &as_they_are)
}

/// The layer for `config`, its images its own.
fn layer(gpu: &Gpu, config: &RenderConfig) -> FoveationLayer {
    FoveationLayer::new(gpu, config).unwrap()
}

fn unchanged(views: Vec<DrawPass>) -> Vec<DrawPass> {
    views
}

fn as_they_are(_: &mut Vec<View>) {}

/// The engine's frame is foveate's renderer's to the pixel: the same views placed, the same
/// masks, the same composition and lens, its own shaders computing what foveate's flat shading
/// computes. Negative control: a fovea view's projection one texel off (next test).
#[test]
fn an_engines_frames_are_foveates_own() {
    let gpu = gpu();
    let config = config(&world(), None);
    let inputs = inputs(world().head, 3);
    let own = renderer_frames(&gpu, &config, &inputs);
    let theirs = plain_engine_frames(&gpu, &config, &inputs);
    let pixels = 2 * 160 * 160;
    assert_eq!(
        differing(&own, &theirs.image),
        0,
        "of {pixels} pixels, these differ from foveate's own frame"
    );
    gpu.check_validation().unwrap();
}

/// Each mistake an engine can make shows: a view's projection a texel off changes the image;
/// the masks' stencil test left out of its pipelines leaves the image as it was but shades
/// more fragments.
#[test]
fn what_an_engine_gets_wrong_shows() {
    let gpu = gpu();
    let world = world();
    let inputs = inputs(world.head, 2);
    let config = config(&world, None);
    let own = renderer_frames(&gpu, &config, &inputs);
    let texel_off = |views: &mut Vec<View>| {
        let v = &mut views[2];
        let ndc = 2.0 / v.extent.width as f32;
        v.clip_from_world = Mat4::from_translation(Vec3::new(ndc, 0.0, 0.0)) * v.clip_from_world;
    };
    let shifted = engine_frames(&gpu, layer(&gpu, &config), &inputs, &unchanged, &texel_off);
    assert!(
        differing(&own, &shifted.image) > 20,
        "a fovea view one texel off changed {} pixels",
        differing(&own, &shifted.image)
    );
    let masked = plain_engine_frames(&gpu, &config, &inputs);
    let no_stencil = |passes: Vec<DrawPass>| {
        (passes.into_iter())
            .map(|p| DrawPass { stencil: None, ..p })
            .collect()
    };
    let unmasked = engine_frames(
        &gpu,
        layer(&gpu, &config),
        &inputs,
        &no_stencil,
        &as_they_are,
    );
    assert_eq!(
        differing(&masked.image, &unmasked.image),
        0,
        "what the masks cut is never shown"
    );
    let (with, without) = (&masked.samples_passed, &unmasked.samples_passed);
    // The periphery's pass and the fovea's, or each eye's of both where the driver needs
    // a pass per view (`DriverQuirks::multiview_clipping_drops_views`).
    assert!(with.len() == 2 || with.len() == 4, "{} passes", with.len());
    let pair = with.len() / 2;
    for (k, (with, without)) in with.chunks(pair).zip(without.chunks(pair)).enumerate() {
        let (with, without) = (with.iter().sum::<u64>(), without.iter().sum::<u64>());
        assert!(
            without > with,
            "view pair {k}: {without} samples shaded without the stencil test, {with} with"
        );
    }
}

/// With the periphery accumulated over frames, the engine's frames stay foveate's own, and one
/// view drawn without its jitter does not.
#[test]
fn the_jitter_an_engine_leaves_out_shows() {
    let gpu = gpu();
    let world = world();
    let inputs = inputs(world.head, 4);
    let config = config(&world, Some(TemporalConfig::default()));
    let own = renderer_frames(&gpu, &config, &inputs);
    let theirs = plain_engine_frames(&gpu, &config, &inputs);
    assert_eq!(
        differing(&own, &theirs.image),
        0,
        "accumulated, still equal"
    );
    let unjittered = |views: &mut Vec<View>| {
        let v = &mut views[0];
        let guard_band = v.viewport.width / v.extent.width as f32;
        let ndc = 2.0 * v.jitter / Vec2::new(v.extent.width as f32, v.extent.height as f32);
        let back = Mat4::from_translation((-ndc / guard_band).extend(0.0));
        v.clip_from_world = back * v.clip_from_world;
    };
    let wrong = engine_frames(&gpu, layer(&gpu, &config), &inputs, &unchanged, &unjittered);
    assert!(
        differing(&own, &wrong.image) > 20,
        "the left periphery without its jitter changed {} pixels",
        differing(&own, &wrong.image)
    );
}

/// The engine's frames into images it made itself — each view image as `view_images`
/// describes (with the periphery accumulated, both images of its depth), and the output the
/// display takes as `output_image_desc` does — are the frames into foveate's own.
#[test]
fn an_engines_own_images_take_the_frames() {
    let gpu = gpu();
    let world = world();
    let inputs = inputs(world.head, 3);
    let config = config(&world, Some(TemporalConfig::default()));
    let handed_out = RenderConfig {
        external_output: true,
        ..config.clone()
    };
    let plan = foveate::plan::plan_for_engine(&handed_out, gpu.caps()).unwrap();
    let needed = view_images(&plan);
    assert!(
        needed.len() >= 5,
        "colour, depth, resolve, a depth pair: {needed:?}"
    );
    let images: Vec<Image> = (needed.iter())
        .map(|v| Image::new(&gpu, &v.desc).unwrap())
        .collect();
    let handed: Vec<HandedImage> = (needed.iter().zip(&images))
        .map(|(v, image)| HandedImage {
            attachment: v.attachment,
            image: image.raw(),
            desc: v.desc,
        })
        .collect();
    let output = Image::new(&gpu, &output_image_desc(&plan)).unwrap();
    let into_output: Vec<FrameInput> = (inputs.iter())
        .map(|i| i.with_output(output.raw()))
        .collect();
    // SAFETY: each image made as described, alive past the layer.
    let theirs = unsafe { FoveationLayer::with_images(&gpu, &plan, &[], &handed) }.unwrap();
    let own = plain_engine_frames(&gpu, &config, &inputs);
    let handed_in = engine_frames(&gpu, theirs, &into_output, &unchanged, &as_they_are);
    assert_eq!(differing(&own.image, &handed_in.image), 0);
    drop((images, output));
    gpu.check_validation().unwrap();
}

/// An image made otherwise than the plan needs, one missing, one for another attachment or
/// one handed twice is refused, naming what is wrong, before anything is made. Mutation:
/// dropping the usage check lets an image without `SAMPLED` through.
#[test]
fn images_an_engine_makes_wrong_are_refused_by_name() {
    let gpu = gpu();
    let config = config(&world(), None);
    let plan = foveate::plan::plan_for_engine(&config, gpu.caps()).unwrap();
    let needed = view_images(&plan);
    // Real images made as the plan needs: a check that failed to refuse would build on them
    // and fail the test by succeeding, not by touching an image that is not there.
    let images: Vec<Image> = (needed.iter())
        .map(|v| Image::new(&gpu, &v.desc).unwrap())
        .collect();
    let all = |change: &dyn Fn(usize, &mut HandedImage)| -> Vec<HandedImage<'static>> {
        (needed.iter().enumerate())
            .map(|(i, v)| {
                let mut h = HandedImage {
                    attachment: v.attachment,
                    image: images[i].raw(),
                    desc: v.desc,
                };
                change(i, &mut h);
                h
            })
            .collect()
    };
    let depth = needed
        .iter()
        .position(|v| v.desc.format != vk::Format::R8G8B8A8_SRGB && v.desc.samples > 1)
        .unwrap();
    let sampled = needed
        .iter()
        .position(|v| v.desc.usage.contains(vk::ImageUsageFlags::SAMPLED))
        .unwrap();
    let cases: Vec<(Vec<HandedImage>, &str)> = vec![
        (
            all(&|i, h| {
                if i == 0 {
                    h.desc.format = vk::Format::B8G8R8A8_UNORM
                }
            }),
            "view image format = B8G8R8A8_UNORM",
        ),
        (
            all(&|i, h| {
                if i == 0 {
                    h.desc.width += 1
                }
            }),
            "view image extent",
        ),
        (
            all(&|i, h| {
                if i == depth {
                    h.desc.samples = 1
                }
            }),
            "view image samples = 1",
        ),
        (
            all(&|i, h| {
                if i == 0 {
                    h.desc.layers = 1
                }
            }),
            "view image layers = 1",
        ),
        (
            all(&|i, h| {
                if i == sampled {
                    h.desc.usage = vk::ImageUsageFlags::COLOR_ATTACHMENT
                }
            }),
            "view image usage",
        ),
        (
            all(&|_, _| {}).into_iter().skip(1).collect(),
            "view images = none for",
        ),
        (
            all(&|i, h| {
                if i == 0 {
                    h.attachment = 1000
                }
            }),
            "view image attachment = 1000",
        ),
    ];
    for (handed, want) in cases {
        // SAFETY: the images are alive past the layer, were it made.
        let err = unsafe { FoveationLayer::with_images(&gpu, &plan, &[], &handed) }
            .err()
            .expect("refused")
            .to_string();
        assert!(err.contains(want), "{want}: {err}");
    }
    drop(images);
    gpu.check_validation().unwrap();
}

// ---- An engine's ground plane: two large triangles under the viewer reaching behind both
// eyes, so every view clips them. Mesa before 25 draws a primitive a multiview pass clips with
// the first view's per-primitive data, into the wrong layer
// (`DriverQuirks::multiview_clipping_drops_views`); the layer then plans an engine's scene
// passes one view at a time. Each view tints what it draws (the example engine's
// `view_tints`: the left eye's views green, the right eye's red), so a primitive drawn by the
// wrong view shows.

/// A ground 400 m across, of two triangles, the head 1.7 m above its centre.
fn ground() -> World {
    let half = 200.0;
    let corner = |x: f32, z: f32| EngineVertex {
        position: [x, 0.0, z],
        normal: [0.0, 1.0, 0.0],
    };
    let mesh = WorldMesh {
        vertices: vec![
            corner(-half, -half),
            corner(-half, half),
            corner(half, half),
            corner(half, -half),
        ],
        indices: vec![0, 1, 2, 0, 2, 3],
        bounds: Sphere::new(Vec3::ZERO, half * 1.5),
    };
    World {
        meshes: vec![mesh],
        objects: vec![WorldObject {
            mesh: 0,
            model: Mat4::IDENTITY,
            colour: Vec4::ONE,
        }],
        light_dir: Vec3::new(0.0, -1.0, 0.0),
        head: Mat4::from_translation(Vec3::new(0.0, 1.7, 0.0)),
        reach: 400.0,
    }
}

/// The library's default foveation at 128² per eye, through the lens.
fn ground_config() -> RenderConfig {
    RenderConfig {
        hmd: "quest-pro".into(),
        resolution: Some(Resolution::square(128)),
        foveation: Some(FoveationConfig::default()),
        far: 500.0,
        ..RenderConfig::default()
    }
}

/// The engine's first frame of the ground through a layer for `plan`, the gaze on the ground
/// in both eyes, each eye's views tinted: the left's green, the right's red.
fn ground_frame(gpu: &Gpu, plan: &FramePlan) -> StereoImage {
    let world = ground();
    let head = world.head;
    let mut layer = FoveationLayer::for_plan(gpu, plan, &[]).unwrap();
    let mut engine = Engine::new(gpu, world, &layer.draw_passes(), layer.frame_slots()).unwrap();
    let (green, red) = (Vec4::new(0.1, 0.8, 0.1, 1.0), Vec4::new(0.8, 0.1, 0.1, 1.0));
    engine.view_tints = std::array::from_fn(|view| if view % 2 == 0 { green } else { red });
    let input = FrameInput::new(head).with_gaze([Vec2::new(0.0, -0.3); 2]);
    let views = layer.views(&input).unwrap();
    engine.write_views(views.slot, &views.views);
    layer.render(&views, &mut |ctx| engine.draw(ctx)).unwrap();
    let image = layer.readback().unwrap();
    drop(engine);
    drop(layer);
    gpu.check_validation().unwrap();
    image
}

/// The plan for `caps` with the clipping quirk as `quirk` says; with it, the resolve quirk too,
/// so that every driver runs the copies a driver with both needs.
fn plan_with_quirk(caps: &DeviceCaps, quirk: bool) -> FramePlan {
    let mut caps = caps.clone();
    caps.quirks.multiview_clipping_drops_views = quirk;
    caps.quirks.layered_resolve_ignores_base_layer |= quirk;
    plan_for_engine(&ground_config(), &caps).unwrap()
}

/// Each eye's share of its pixels tinted green, and of those tinted red.
fn tinted(image: &StereoImage) -> [[f64; 2]; 2] {
    image.eyes().map(|eye| {
        let share = |channel: usize| {
            let tinted = eye.data.chunks(4).filter(|p| {
                let others = (0..3).filter(|&c| c != channel);
                others.map(|c| p[c]).max().unwrap() as u16 + 60 < p[channel] as u16
            });
            tinted.count() as f64 / (eye.width * eye.height) as f64
        };
        [share(1), share(0)]
    })
}

/// The frame as the layer plans it for this driver shows the ground in each eye drawn by that
/// eye's views alone, in the same share (the Quest Pro's eyes mirror each other), and equals
/// the frame whose every scene pass draws one view. Negative control, where the driver has the
/// quirk: the same frame planned multiview (the quirk ignored) draws right-eye primitives into
/// the left eye.
#[test]
fn an_engines_ground_plane_is_drawn_by_each_eyes_own_views() {
    let gpu = gpu();
    let caps = gpu.caps();
    let quirk = caps.quirks.multiview_clipping_drops_views;
    let as_planned = plan_for_engine(&ground_config(), caps).unwrap();
    let one_view_each = plan_with_quirk(caps, true);
    let most_views = |plan: &FramePlan| {
        let scene = plan.passes.iter().filter(|p| p.kind == PassKind::Scene);
        scene.map(|p| p.view_mask.count_ones()).max().unwrap()
    };
    assert_eq!(most_views(&as_planned), if quirk { 1 } else { 2 });
    assert_eq!(most_views(&one_view_each), 1);
    let image = ground_frame(&gpu, &as_planned);
    let [[left_green, left_red], [right_green, right_red]] = tinted(&image);
    let reference = ground_frame(&gpu, &one_view_each);
    let differ = differing(&image, &reference);
    eprintln!(
        "{}: ground {left_green:.3} green, {left_red:.3} red in the left eye, \
         {right_green:.3} green, {right_red:.3} red in the right; {differ} pixels differ \
         from the frame of one view a pass",
        gpu.info().driver
    );
    assert!(left_green > 0.3 && left_red == 0.0, "left eye");
    assert!(
        right_green == 0.0 && (right_red - left_green).abs() < 0.01,
        "right eye"
    );
    assert_eq!(differ, 0);
    if quirk {
        let multiview = ground_frame(&gpu, &plan_with_quirk(caps, false));
        let [[_, left_red], _] = tinted(&multiview);
        eprintln!("planned multiview: {left_red:.3} of the left eye drawn by the right's views");
        assert!(left_red > 0.01, "the quirk no longer shows: drop it");
    }
}
