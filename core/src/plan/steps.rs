//! What a pass does, as an ordered list of steps, each with the stencil state it runs under:
//! the renderer records them in order and decides nothing. Stencil bits are allocated here.

use std::fmt;

use crate::view::Eye;

/// Which instances a scene pass draws.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DrawSet {
    /// Every instance, straight from the scene's draws.
    All,
    /// Instances the culling strategy keeps for the pass's views (culled per frame).
    Visible,
    /// Instances one eye's own frustum keeps: per-eye culling of a two-pass frame.
    VisibleToEye(Eye),
    /// Instances reaching in front of the MFFR split (culled per frame).
    NearField,
    /// Instances reaching beyond the MFFR far pass's near plane (culled per frame).
    FarField,
    /// Instances the superfrustum of the two fovea frusta keeps: the fovea pass of the
    /// two-pass fovea layout (culled per frame).
    Fovea,
    /// The periphery's instances (every one, or the culling strategy's), each tagged with
    /// whether the fovea superfrustum keeps it: the one-pass fovea layout, whose vertex shader
    /// emits no primitives in the fovea views for untagged instances (culled per frame).
    FoveaTagged,
}

/// A step of a pass that shades fragments, counted on its own in counting frames.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum CountedStep {
    /// Stencil mask fans (the HMD mask, foveation's inset/outset), at the start of the pass.
    Mask,
    /// The MFFR far image composited into the eye views.
    FarComposite,
    /// The scene's meshes.
    Scene,
    /// The coverage probe's full-view draw.
    Probe,
    /// The output stage (with foveation, the composition of each eye at full resolution).
    Output,
    /// Radial density masking's mask (a full-view draw) and its reconstruction.
    RadialMask,
    /// Radial density reconstruction (a full-view draw per eye).
    Reconstruct,
    /// A view's resolve copied into its layer (a full-view draw).
    LayerCopy,
}

impl CountedStep {
    /// Its name in the printout and in per-view fragment counts.
    pub fn name(self) -> &'static str {
        match self {
            CountedStep::Mask => "mask",
            CountedStep::FarComposite => "far composite",
            CountedStep::Scene => "scene",
            CountedStep::Probe => "probe",
            CountedStep::Output => "output",
            CountedStep::RadialMask => "radial mask",
            CountedStep::Reconstruct => "reconstruct",
            CountedStep::LayerCopy => "layer copy",
        }
    }
}

/// Stencil bit 0: set where the masks keep a pixel (the lens-visible area, a fovea's inset
/// circle, a periphery outside its hole). Bit 1: set where the MFFR near field drew
/// (near-first), so the far composite fills only what it left.
pub const MASK_BIT: u32 = 1;
/// Stencil bit 1 (see [`MASK_BIT`]).
pub const NEAR_BIT: u32 = 2;
/// Stencil bit 2: set on the quads radial density masking skips.
pub const SKIP_BIT: u32 = 4;

#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
/// A stencil comparison.
pub enum CompareOp {
    /// Always passes.
    Always,
    /// Passes where the masked stencil value equals the masked reference.
    Equal,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
/// What a passing fragment does to the stencil value.
pub enum StencilOp {
    /// Keeps it.
    Keep,
    /// Replaces it with the reference (through the write mask).
    Replace,
}

/// A step's stencil test and write (front and back alike).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct StencilState {
    /// The test.
    pub compare: CompareOp,
    /// The bits the test compares.
    pub compare_mask: u32,
    /// The value compared with, and written by `Replace`.
    pub reference: u32,
    /// What a passing fragment does to the stencil value (failing ones keep it).
    pub pass: StencilOp,
    /// The bits a write may change.
    pub write_mask: u32,
}

/// One thing a pass does, in the order the pass does it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Step {
    /// Stencil mask fans, before anything else: every view's keep shapes written as
    /// `MASK_BIT`, then its drop shapes cleared (the reference is set per fan set), then —
    /// with `hidden_area` — a runtime's hidden-area triangles cleared too.
    MaskFans {
        /// How the fans write the stencil.
        stencil: StencilState,
        /// Whether a runtime's hidden-area triangles are cleared too.
        hidden_area: bool,
    },
    /// The MFFR far image composited into every view: first (the near field drawn over it)
    /// or after the scene into the pixels it left (near-first).
    FarComposite {
        /** The stencil test of the near-first composite, if any. */
        stencil: Option<StencilState>,
    },
    /// The scene's meshes: `draw_set`, culled each frame into the plan's cull slot `cull_slot`
    /// unless it is every instance.
    Scene {
        /// The instances drawn.
        draw_set: DrawSet,
        /// The plan's cull slot that culls them each frame, if they are culled.
        cull_slot: Option<usize>,
        /// The stencil test (masks), if any.
        stencil: Option<StencilState>,
    },
    /// The coverage probe: a full-view draw under the masks, counted per view.
    Probe {
        /** The stencil test (masks), if any. */
        stencil: Option<StencilState>,
    },
    /// Radial density masking: a full-view draw marking the skipped quads (`SKIP_BIT`).
    RadialMask {
        /** How the mask marks the skipped quads. */
        stencil: StencilState,
    },
    /// Radial density reconstruction: a full-view draw per eye filling the skipped quads.
    Reconstruct,
    /// A view's image, which its pass resolved alone, copied texel for texel into its layer
    /// of the image the frame samples (a full-view draw), where the driver's in-pass resolve
    /// cannot land in a layer ([`DriverQuirks`](super::DriverQuirks)`::layered_resolve_ignores_base_layer`).
    LayerCopy {
        /** The image copied (the pass's one sampled attachment). */
        from: super::ops::AttachmentId,
    },
    /// The output stage: a full-view draw per eye sampling what the frame rendered, composing a
    /// foveated frame's views and, for the lens, pre-distorting.
    Output(OutputStep),
}

/// What the output stage does.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct OutputStep {
    /// Pre-distort for the headset's lens (`OutputStage::Lens`), or not.
    pub lens: bool,
    /// Where each eye's rendered image lies in the pass's sampled attachments.
    pub source: OutputSource,
    /// The periphery accumulated over frames in this pass: the history reprojected by depth,
    /// read from the pass's last two sampled images (the history, the periphery's depth), the
    /// next history written beside the output (the pass's `history`).
    pub temporal: bool,
    /// The pass accumulates the periphery alone at its own texels
    /// ([`HistoryAt::Periphery`](crate::foveation::HistoryAt::Periphery)): no fovea over it,
    /// no lens; the output pass composes what it writes.
    pub periphery_only: bool,
}

/// Where the output stage finds each eye's rendered image.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum OutputSource {
    /// Eye `e` is layer `e` of the first sampled image.
    Layered,
    /// Both eyes side by side in the first sampled image.
    SideBySide,
    /// Eye `e` is the `e`-th sampled image.
    PerEye,
    /// A foveated frame: eye `e`'s periphery is layer `e` of the first sampled image, its fovea
    /// layer `fovea_layer + e` of the last (the same image for the one-pass layout); with
    /// `sharpen`, the periphery is sharpened as it is upscaled.
    Foveated {
        /** The first layer of the fovea views in the last sampled image. */
        fovea_layer: u32,
        /** Whether the periphery is sharpened as it is upscaled. */
        sharpen: bool,
    },
}

impl OutputSource {
    /// The shader's `SOURCE` constant (see `shaders/output.frag`).
    pub fn code(self) -> u32 {
        match self {
            OutputSource::Layered => 0,
            OutputSource::SideBySide => 1,
            OutputSource::PerEye => 2,
            OutputSource::Foveated { .. } => 3,
        }
    }
}

impl Step {
    /// A scene step drawing `draw_set` (its cull slot and stencil assigned later).
    pub(crate) fn scene(draw_set: DrawSet) -> Step {
        Step::Scene {
            draw_set,
            cull_slot: None,
            stencil: None,
        }
    }

    /// What a counting frame calls this step's fragments.
    pub fn counted(&self) -> CountedStep {
        match self {
            Step::MaskFans { .. } => CountedStep::Mask,
            Step::FarComposite { .. } => CountedStep::FarComposite,
            Step::Scene { .. } => CountedStep::Scene,
            Step::Probe { .. } => CountedStep::Probe,
            Step::Output(_) => CountedStep::Output,
            Step::RadialMask { .. } => CountedStep::RadialMask,
            Step::Reconstruct => CountedStep::Reconstruct,
            Step::LayerCopy { .. } => CountedStep::LayerCopy,
        }
    }

    /// The step's stencil test, if it has one.
    pub fn stencil(&self) -> Option<StencilState> {
        match *self {
            Step::MaskFans { stencil, .. } | Step::RadialMask { stencil } => Some(stencil),
            Step::FarComposite { stencil }
            | Step::Scene { stencil, .. }
            | Step::Probe { stencil } => stencil,
            Step::Output(_) | Step::Reconstruct | Step::LayerCopy { .. } => None,
        }
    }
}

/// A step's stencil before `derive` assigns it (builders add steps; the rule below decides).
pub(crate) fn stencil_placeholder() -> StencilState {
    StencilState {
        compare: CompareOp::Always,
        compare_mask: 0,
        reference: 0,
        pass: StencilOp::Keep,
        write_mask: 0,
    }
}

/// The stencil state of every step of a pass, from which stencil-writing steps it has: mask
/// fans (bit 0 kept), a near-first far composite (bit 1 marks the near field) and a radial
/// density mask (bit 2 marks skipped quads).
pub(crate) fn assign_stencil_states(steps: &mut [Step]) {
    let has = |f: fn(&Step) -> bool| steps.iter().any(f);
    let masks = has(|s| matches!(s, Step::MaskFans { .. }));
    let skip = has(|s| matches!(s, Step::RadialMask { .. }));
    let far = steps
        .iter()
        .position(|s| matches!(s, Step::FarComposite { .. }));
    let scene = steps.iter().position(|s| matches!(s, Step::Scene { .. }));
    let near_first = matches!((far, scene), (Some(f), Some(s)) if f > s);
    let state = |compare, compare_mask, reference, pass, write_mask| StencilState {
        compare,
        compare_mask,
        reference,
        pass,
        write_mask,
    };
    let bit = |on: bool, bit: u32| if on { bit } else { 0 };
    // What a kept pixel has: the mask bit where masks run, no skip bit.
    let kept_mask = bit(masks, MASK_BIT) | bit(skip, SKIP_BIT);
    let kept = bit(masks, MASK_BIT);
    for step in steps.iter_mut() {
        match step {
            // Keep shapes write the mask bit, drop shapes clear it (reference set per fan set).
            Step::MaskFans { stencil, .. } => {
                *stencil = state(CompareOp::Always, 0, 0, StencilOp::Replace, MASK_BIT)
            }
            Step::RadialMask { stencil } => {
                *stencil = state(CompareOp::Always, 0, SKIP_BIT, StencilOp::Replace, SKIP_BIT)
            }
            // Tested against the masks and the skipped quads; near-first marks what it covers.
            Step::Scene { stencil, .. } => {
                *stencil = (masks || skip || near_first).then(|| {
                    state(
                        if masks || skip {
                            CompareOp::Equal
                        } else {
                            CompareOp::Always
                        },
                        kept_mask,
                        kept | bit(near_first, NEAR_BIT),
                        if near_first {
                            StencilOp::Replace
                        } else {
                            StencilOp::Keep
                        },
                        bit(near_first, NEAR_BIT),
                    )
                })
            }
            Step::Probe { stencil } => {
                *stencil = (masks || skip)
                    .then(|| state(CompareOp::Equal, kept_mask, kept, StencilOp::Keep, 0))
            }
            // Only kept pixels the near field left uncovered (near-first), or every kept pixel.
            Step::FarComposite { stencil } => {
                *stencil = (masks || near_first).then(|| {
                    state(
                        CompareOp::Equal,
                        kept_mask | bit(near_first, NEAR_BIT),
                        kept,
                        StencilOp::Keep,
                        0,
                    )
                })
            }
            Step::Output(_) | Step::Reconstruct | Step::LayerCopy { .. } => {}
        }
    }
}

impl fmt::Display for StencilState {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let compare = match self.compare {
            CompareOp::Always => "always".to_string(),
            CompareOp::Equal => format!(
                "(s & {:#04b}) == {:#04b}",
                self.compare_mask,
                self.reference & self.compare_mask
            ),
        };
        write!(f, "stencil {compare}")?;
        if self.write_mask != 0 && self.pass == StencilOp::Replace {
            write!(f, ", writes bits {:#04b}", self.write_mask)?;
        }
        Ok(())
    }
}

impl fmt::Display for Step {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let name = match self {
            Step::MaskFans { .. } => "mask fans".to_string(),
            Step::FarComposite { .. } => "far composite".to_string(),
            Step::Scene {
                cull_slot: Some(slot),
                ..
            } => format!("scene (cull slot {slot})"),
            Step::Scene { .. } => "scene".to_string(),
            Step::Probe { .. } => "probe".to_string(),
            Step::Output(o) if o.periphery_only => {
                "output (the periphery alone, at its own texels, accumulated)".to_string()
            }
            Step::Output(o) => {
                format!(
                    "output ({}{})",
                    match o.source {
                        OutputSource::Foveated { sharpen: false, .. } => "fovea over periphery",
                        OutputSource::Foveated { sharpen: true, .. } =>
                            "fovea over sharpened periphery",
                        _ => "eye images",
                    },
                    if o.lens {
                        ", lens-distorted"
                    } else {
                        ", undistorted"
                    }
                ) + if o.temporal {
                    ", periphery accumulated"
                } else {
                    ""
                }
            }
            Step::RadialMask { .. } => "radial mask".to_string(),
            Step::Reconstruct => "reconstruct".to_string(),
            Step::LayerCopy { from } => format!("copy #{from} into its layer"),
        };
        match self.stencil() {
            Some(s) => write!(f, "{name} [{s}]"),
            None => f.write_str(&name),
        }
    }
}
