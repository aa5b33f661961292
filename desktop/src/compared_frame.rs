//! The frame the comparing commands measure against and vary.

use anyhow::Result;
use clap::Args;
use foveate::plan::{RenderConfig, Resolution, StereoMode};
use foveate::scene::Scene;

use crate::frame_args::{profile, scene_from, screen, ClusterArgs, HeadArgs};

/// The frame the comparing commands (`compare`, `flicker`) measure against and vary; the
/// scene and resolution are each command's, with defaults of its own.
#[derive(Args, Clone)]
pub struct ComparedFrame {
    /// Headset profile (`foveate plan --hmd NAME` prints its figures): its field of view, lens
    /// and, with `--res native`, its panel.
    #[arg(long, default_value = "index")]
    pub hmd: String,
    /// Shading: flat or lit (default: the scene's own).
    #[arg(long)]
    pub shading: Option<String>,
    /// What the frame's last pass writes: lens (pre-distorted, the display's image) or
    /// undistorted. Errors are measured on it.
    #[arg(long, default_value = "lens")]
    pub output: String,
    /// Fovea layout of the foveated rows: auto, one-pass or two-pass.
    #[arg(long, default_value = "auto")]
    pub fovea_layout: String,
    /// Also measure every single-frame foveated row with its periphery's highlights
    /// prefiltered (`--periphery-prefilter`), each beside its row: lit scenes only.
    #[arg(long)]
    pub prefilter: bool,
    /// Also measure every single-frame foveated row with a parafoveal ring of each of these
    /// ratios (`--ring`), each beside its row.
    #[arg(long, value_delimiter = ',', value_name = "RATIOS")]
    pub rings: Vec<f32>,
    #[command(flatten)]
    pub head: HeadArgs,
    #[command(flatten)]
    pub clusters: ClusterArgs,
}

impl ComparedFrame {
    /// The scene `name`, shaded, clustered and its head placed as asked.
    pub fn scene(&self, name: &str) -> Result<Scene> {
        scene_from(name, self.shading.as_deref(), &self.head, &self.clusters)
    }

    /// The per-eye screen of `res` (N, WxH or `native`) on this frame's headset.
    pub fn screen(&self, res: &str) -> Result<Resolution> {
        screen(&self.hmd, res)
    }

    /// The multiview stereo frame on the headset at `res` (N, WxH or `native`) per eye.
    pub fn base(&self, res: &str) -> Result<RenderConfig> {
        Ok(RenderConfig {
            hmd: profile(&self.hmd)?.name.to_string(),
            resolution: Some(self.screen(res)?),
            stereo: StereoMode::Multiview,
            output: self.output.parse()?,
            fovea_layout: self.fovea_layout.parse()?,
            lod: self.clusters.lod()?,
            ..RenderConfig::default()
        })
    }
}
