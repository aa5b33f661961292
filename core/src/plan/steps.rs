//! What a pass does, as an ordered list of steps, each with the stencil state it runs under:
//! the renderer records them in order and decides nothing. Stencil bits are allocated here.

use std::fmt;

use super::DrawSet;

/// Stencil bit 0: set where the masks keep a pixel (the lens-visible area, a fovea's inset
/// circle, a periphery outside its hole). Bit 1: set where the MFFR near field drew
/// (near-first), so the far composite fills only what it left.
pub const MASK_BIT: u32 = 1;
pub const NEAR_BIT: u32 = 2;
/// Stencil bit 2: set on the quads radial density masking skips.
pub const SKIP_BIT: u32 = 4;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CompareOp {
    Always,
    Equal,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StencilOp {
    Keep,
    Replace,
}

/// A step's stencil test and write (front and back alike).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct StencilState {
    pub compare: CompareOp,
    pub compare_mask: u32,
    pub reference: u32,
    /// What a passing fragment does to the stencil value (failing ones keep it).
    pub pass: StencilOp,
    pub write_mask: u32,
}

/// One thing a pass does, in the order the pass does it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Step {
    /// Stencil mask fans, before anything else: every view's keep shapes written as
    /// `MASK_BIT`, then its drop shapes cleared (the reference is set per fan set).
    MaskFans { stencil: StencilState },
    /// The MFFR far image composited into every view: first (the near field drawn over it)
    /// or after the scene into the pixels it left (near-first).
    FarComposite { stencil: Option<StencilState> },
    /// The scene's meshes: `draw_set`, culled each frame into the plan's cull slot `cull_slot`
    /// unless it is every instance.
    Scene {
        draw_set: DrawSet,
        cull_slot: Option<usize>,
        stencil: Option<StencilState>,
    },
    /// The coverage probe: a full-view draw under the masks, counted per view.
    Probe { stencil: Option<StencilState> },
    /// Radial density masking: a full-view draw marking the skipped quads (`SKIP_BIT`).
    RadialMask { stencil: StencilState },
    /// Radial density reconstruction: a full-view draw per eye filling the skipped quads.
    Reconstruct,
    /// Foveated composition: a full-view draw per eye sampling the four views.
    Composite,
}

impl Step {
    pub fn stencil(&self) -> Option<StencilState> {
        match *self {
            Step::MaskFans { stencil } | Step::RadialMask { stencil } => Some(stencil),
            Step::FarComposite { stencil }
            | Step::Scene { stencil, .. }
            | Step::Probe { stencil } => stencil,
            Step::Composite | Step::Reconstruct => None,
        }
    }
}

/// The stencil states of a scene pass's steps, from what the pass has: masks and/or an MFFR
/// near-first composite. (mask fans, scene, probe, far composite.)
pub(crate) fn stencil_states(
    masks: bool,
    near_first: bool,
) -> (
    StencilState,
    Option<StencilState>,
    Option<StencilState>,
    Option<StencilState>,
) {
    let state = |compare, compare_mask, reference, pass, write_mask| StencilState {
        compare,
        compare_mask,
        reference,
        pass,
        write_mask,
    };
    // Keep shapes write MASK_BIT, drop shapes clear it (the reference is set per fan set).
    let fans = state(CompareOp::Always, 0, 0, StencilOp::Replace, MASK_BIT);
    // Tested against the masks; near-first marks what the near field covers.
    let scene = (masks || near_first).then(|| {
        state(
            if masks {
                CompareOp::Equal
            } else {
                CompareOp::Always
            },
            MASK_BIT,
            MASK_BIT | NEAR_BIT,
            if near_first {
                StencilOp::Replace
            } else {
                StencilOp::Keep
            },
            if near_first { NEAR_BIT } else { 0 },
        )
    });
    let probe = masks.then(|| state(CompareOp::Equal, MASK_BIT, MASK_BIT, StencilOp::Keep, 0));
    // Only kept pixels the near field left uncovered (near-first), or every kept pixel.
    let far = (masks || near_first).then(|| {
        let masked = if masks { MASK_BIT } else { 0 };
        state(
            CompareOp::Equal,
            masked | if near_first { NEAR_BIT } else { 0 },
            masked,
            StencilOp::Keep,
            0,
        )
    });
    (fans, scene, probe, far)
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
            Step::Composite => "composite".to_string(),
            Step::RadialMask { .. } => "radial mask".to_string(),
            Step::Reconstruct => "reconstruct".to_string(),
        };
        match self.stencil() {
            Some(s) => write!(f, "{name} [{s}]"),
            None => f.write_str(&name),
        }
    }
}
