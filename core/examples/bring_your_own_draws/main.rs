//! Foveation for an engine's own draws: the engine keeps its world, its vertex layout, its
//! shaders and pipelines (`engine.rs`, raw Vulkan); foveate places the views, masks them, and
//! composes what the engine drew into the output the display shows. Per frame: the views, the
//! engine's uniforms from them, then one recorded frame — at each pass the masks, the engine's
//! draws, and after the last the output stage.
//!
//! ```text
//! cargo run -p foveate --example bring_your_own_draws [-- path/to/scene.glb]
//! ```
//!
//! Without a path it draws assimp's 2-cylinder engine from Debian's `assimp-testmodels`.

mod engine;

use std::path::PathBuf;

use foveate::foveation::FoveationConfig;
use foveate::glam::Vec2;
use foveate::gpu::{Gpu, GpuOptions};
use foveate::plan::{OutputStage, RenderConfig, Resolution};
use foveate::render::{FoveationLayer, FrameInput};

const DEFAULT_SCENE: &str =
    "/usr/share/assimp/models/glTF2/2CylinderEngine-glTF-Binary/2CylinderEngine.glb";

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let path = std::env::args_os()
        .nth(1)
        .map_or_else(|| PathBuf::from(DEFAULT_SCENE), PathBuf::from);
    if !path.exists() {
        return Err(format!(
            "{}: no such scene file (give a glTF file, or install Debian's assimp-testmodels)",
            path.display()
        )
        .into());
    }
    let world = engine::World::from_gltf(&path)?;
    let gpu = Gpu::new(&GpuOptions::default())?;
    // What the display needs, and of the engine's world only how far it reaches: a headset,
    // its resolution, foveation, the lens, the depth range.
    let config = RenderConfig {
        hmd: "quest-pro".into(),
        resolution: Some(Resolution::square(512)),
        foveation: Some(FoveationConfig::default()),
        output: OutputStage::Lens,
        far: world.reach.max(RenderConfig::default().far),
        ..RenderConfig::default()
    };
    let mut layer = FoveationLayer::new(&gpu, &config)?;
    let passes = layer.draw_passes();
    for pass in &passes {
        println!(
            "the engine draws pass {} \"{}\": views {:?}, {}x{}, {}x MSAA, stencil test {}",
            pass.index,
            pass.name,
            pass.views,
            pass.extent.width,
            pass.extent.height,
            pass.samples.as_raw(),
            if pass.stencil.is_some() { "on" } else { "off" }
        );
    }
    let head = world.head;
    let mut engine = engine::Engine::new(&gpu, world, &passes, layer.frame_slots())?;
    for frame in 0..4 {
        let gaze = Vec2::new(-0.3 + 0.2 * frame as f32, 0.1);
        let input = FrameInput::new(head).with_gaze([gaze; 2]);
        // The frame's views first: the engine's uniforms for its slot come from them, and the
        // frame recorded is theirs.
        let views = layer.views(&input)?;
        engine.write_views(views.slot, &views.views);
        let stats = layer.render(&views, &mut |pass| engine.draw(pass))?;
        println!(
            "frame {frame}, gaze ({:.1}, {:.1}): {} draws in all passes; GPU {:.2} ms ({})",
            gaze.x,
            gaze.y,
            engine.drawn,
            stats.gpu_ms.unwrap_or(0.0),
            stats
                .gpu_pass_times()
                .map(|(pass, ms)| format!("{pass} {ms:.2}"))
                .collect::<Vec<_>>()
                .join(", ")
        );
    }
    let eyes = layer.readback()?;
    let out = std::env::temp_dir().join("foveate-bring-your-own-draws.png");
    eyes.side_by_side().save(&out)?;
    println!(
        "saved {} (left eye, right eye, through the lens)",
        out.display()
    );
    drop(engine);
    drop(layer);
    gpu.check_validation()?;
    Ok(())
}
