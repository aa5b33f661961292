//! A step's pipeline as a value: its shaders, its named specialisation constants and its
//! fixed-function state. The builder that adds a step states it; the renderer compiles it as it
//! is, and its pipeline cache is keyed by it (with the pass's samples, render pass and layout).

use std::fmt;

use super::steps::StencilState;
use crate::shaders::ShaderBinary;

/// A specialisation constant of the shaders, named as the GLSL names it. Its id is declared
/// here once: a test reads every `layout(constant_id = …)` in `shaders/` and fails where the
/// GLSL and this table disagree.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Constant {
    /// Where the view index comes from: 0 `gl_ViewIndex`, 1 a push constant, 2 the instance.
    ViewSource,
    /// The guard band's clip-space scale (1 / guard band).
    ClipXyScale,
    /// MFFR depth shift: the far composite writes the split's depth.
    DepthShift,
    /// The far pass writes depth into alpha.
    DepthInAlpha,
    /// The scene marks instances that move with alpha 0 (for `HistoryClip::Moved`).
    MarkMoving,
    /// The step's first fragment-counter slot (counting shader variants only).
    CounterBase,
    /// The frame view the pass's view 0 is.
    FirstView,
    /// The one-pass fovea layout: untagged instances emit nothing in the fovea views.
    FoveaTags,
    /// Radial density masking: the view's size, the radii and each eye's lens ellipse.
    ViewWidth,
    /// Radial density masking: the view's height.
    ViewHeight,
    /// Radial density masking: the inner radius.
    Inner,
    /// Radial density masking: the outer radius.
    Outer,
    /// Radial density masking: the left lens ellipse's centre x.
    LeftCx,
    /// Radial density masking: the left lens ellipse's centre y.
    LeftCy,
    /// Radial density masking: the left lens ellipse's radius x.
    LeftRx,
    /// Radial density masking: the left lens ellipse's radius y.
    LeftRy,
    /// Radial density masking: the right lens ellipse's centre x.
    RightCx,
    /// Radial density masking: the right lens ellipse's centre y.
    RightCy,
    /// Radial density masking: the right lens ellipse's radius x.
    RightRx,
    /// Radial density masking: the right lens ellipse's radius y.
    RightRy,
    /// The output stage: pre-distort for the lens.
    Lens,
    /// The output stage: where the eyes' images lie ([`super::OutputSource::code`]).
    Source,
    /// The output stage: the fovea views' first layer.
    FoveaLayer,
    /// The output stage: sharpen the periphery as it is upscaled.
    Sharpen,
    /// The output stage: upscale the periphery with Catmull-Rom rather than bilinearly.
    CatmullRom,
    /// The accumulating output stage of a counting frame: the first of its history-outcome
    /// counter slots (the plan's `history_outcome_base`).
    HistoryOutcomeBase,
    /// The accumulating output stage: read the history with Catmull-Rom where the point moved
    /// (`HistoryFilter::CatmullRom`): a constant, so a frame without it compiles none of it.
    HistoryCatmullRom,
    /// The accumulating output stage: the clip's box from a cross of five periphery texels
    /// rather than the 3×3 (`ClipNeighbourhood::Cross`).
    CrossNeighbourhood,
    /// The accumulating output stage: the new sample from the 3×3 periphery texels, each
    /// weighted by its distance, rather than the nearest alone, where the point moved
    /// (`NewSample::Weighted`).
    WeightedNewSample,
    /// The output stage accumulating the periphery alone at its own texels
    /// (`HistoryAt::Periphery`): it writes the accumulated periphery, and the history over the
    /// periphery's hole what the fovea shows.
    PeripheryOnly,
    /// The accumulating output stage accumulates only within a reach of the gaze
    /// (`TemporalConfig::within_deg`): without it, the reach's test is compiled out.
    Reach,
    /// Lit scenes: the periphery views widen each highlight by the spread of the normals their
    /// coarser pixels average
    /// ([`FoveationConfig::periphery_prefilter`](crate::foveation::FoveationConfig::periphery_prefilter)).
    PeripheryPrefilter,
    /// The output stage composes a parafoveal ring between the fovea and the periphery
    /// ([`FoveationConfig::ring_ratio`](crate::foveation::FoveationConfig::ring_ratio)).
    Ring,
    /// The accumulating output stage keeps the periphery's luma alone in its history
    /// ([`HistoryFormat::Luma`](crate::foveation::HistoryFormat::Luma)).
    LumaHistory,
    /// Lit scenes: the point lights each fragment shades (the plan's `point_lights`), so the
    /// loop over them has a bound fixed when the pipeline is compiled.
    PointLights,
}

/// How a constant's 32 bits read.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ConstantKind {
    /// An unsigned integer.
    Uint,
    /// A 32-bit float.
    Float,
    /// A boolean (0 or 1).
    Bool,
}

impl Constant {
    /// Every constant, for the check against the GLSL.
    pub const ALL: [Constant; 35] = {
        use Constant::*;
        [
            ViewSource,
            ClipXyScale,
            DepthShift,
            DepthInAlpha,
            MarkMoving,
            CounterBase,
            FirstView,
            FoveaTags,
            ViewWidth,
            ViewHeight,
            Inner,
            Outer,
            LeftCx,
            LeftCy,
            LeftRx,
            LeftRy,
            RightCx,
            RightCy,
            RightRx,
            RightRy,
            Lens,
            Source,
            FoveaLayer,
            Sharpen,
            CatmullRom,
            HistoryOutcomeBase,
            HistoryCatmullRom,
            CrossNeighbourhood,
            WeightedNewSample,
            PeripheryOnly,
            Reach,
            PeripheryPrefilter,
            Ring,
            PointLights,
            LumaHistory,
        ]
    };

    /// Its `constant_id`, its GLSL name and how its bits read.
    pub fn declaration(self) -> (u32, &'static str, ConstantKind) {
        use Constant::*;
        use ConstantKind::*;
        match self {
            ViewSource => (0, "VIEW_SOURCE", Uint),
            ClipXyScale => (1, "CLIP_XY_SCALE", Float),
            DepthShift => (2, "DEPTH_SHIFT", Bool),
            DepthInAlpha => (3, "DEPTH_IN_ALPHA", Bool),
            MarkMoving => (7, "MARK_MOVING", Bool),
            CounterBase => (4, "COUNTER_BASE", Uint),
            FirstView => (5, "FIRST_VIEW", Uint),
            FoveaTags => (6, "FOVEA_TAGS", Bool),
            ViewWidth => (10, "VIEW_WIDTH", Float),
            ViewHeight => (11, "VIEW_HEIGHT", Float),
            Inner => (12, "INNER", Float),
            Outer => (13, "OUTER", Float),
            LeftCx => (14, "LEFT_CX", Float),
            LeftCy => (15, "LEFT_CY", Float),
            LeftRx => (16, "LEFT_RX", Float),
            LeftRy => (17, "LEFT_RY", Float),
            RightCx => (18, "RIGHT_CX", Float),
            RightCy => (19, "RIGHT_CY", Float),
            RightRx => (20, "RIGHT_RX", Float),
            RightRy => (21, "RIGHT_RY", Float),
            Lens => (30, "LENS", Bool),
            Source => (31, "SOURCE", Uint),
            FoveaLayer => (32, "FOVEA_LAYER", Uint),
            Sharpen => (33, "SHARPEN", Bool),
            CatmullRom => (34, "CATMULL_ROM", Bool),
            HistoryOutcomeBase => (35, "HISTORY_OUTCOME_BASE", Uint),
            HistoryCatmullRom => (36, "HISTORY_CATMULL_ROM", Bool),
            CrossNeighbourhood => (37, "CROSS_NEIGHBOURHOOD", Bool),
            WeightedNewSample => (38, "WEIGHTED_NEW_SAMPLE", Bool),
            PeripheryOnly => (39, "PERIPHERY_ONLY", Bool),
            Reach => (40, "REACH", Bool),
            PeripheryPrefilter => (41, "PERIPHERY_PREFILTER", Bool),
            Ring => (42, "RING", Bool),
            PointLights => (43, "POINT_LIGHTS", Uint),
            LumaHistory => (44, "LUMA_HISTORY", Bool),
        }
    }

    /// Its `constant_id` in the GLSL.
    pub fn id(self) -> u32 {
        self.declaration().0
    }
}

/// Which vertices a pipeline reads.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum VertexInput {
    /// None: the shader generates its vertices (full-view triangles, mask fans).
    Generated,
    /// The scene's vertex buffer (`scene::Vertex`: position, normal, uv, tangent).
    SceneVertices,
}

/// A pipeline as the plan states it. Samples come from the pass's colour attachment.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct PipelineDesc {
    /// The vertex shader.
    pub vertex: &'static ShaderBinary,
    /// The fragment shader.
    pub fragment: &'static ShaderBinary,
    /// Values (raw bits) of the constants the two shaders declare, in [`Constant`] order.
    pub constants: Vec<(Constant, u32)>,
    /// Which vertices it reads.
    pub vertex_input: VertexInput,
    /// Back faces culled (counter-clockwise faces the viewer); masks and full-view draws are
    /// two-dimensional and cull nothing.
    pub cull_back_faces: bool,
    /// Depth tested (reverse-Z: nearer is greater) and written.
    pub depth_test: bool,
    /// Depth clamped instead of clipped at the near and far planes.
    pub depth_clamp: bool,
    /// Its stencil test and write, if any.
    pub stencil: Option<StencilState>,
    /// The stencil reference set per draw, not by the pipeline (mask fans).
    pub dynamic_stencil_reference: bool,
    /// Whether it writes colour (mask fans write only stencil).
    pub writes_colour: bool,
}

impl PipelineDesc {
    /// `vertex` then `fragment`, with no constants, no depth, nothing culled, colour written.
    pub fn new(vertex: &'static ShaderBinary, fragment: &'static ShaderBinary) -> Self {
        PipelineDesc {
            vertex,
            fragment,
            constants: Vec::new(),
            vertex_input: VertexInput::Generated,
            cull_back_faces: false,
            depth_test: false,
            depth_clamp: false,
            stencil: None,
            dynamic_stencil_reference: false,
            writes_colour: true,
        }
    }

    /// Sets `constant` to `bits` where either shader declares it (elsewhere it would only
    /// split the pipeline cache).
    pub fn constant(mut self, constant: Constant, bits: u32) -> Self {
        let id = constant.id();
        if !self.vertex.spec_ids().contains(&id) && !self.fragment.spec_ids().contains(&id) {
            return self;
        }
        match self.constants.binary_search_by_key(&constant, |c| c.0) {
            Ok(i) => self.constants[i].1 = bits,
            Err(i) => self.constants.insert(i, (constant, bits)),
        }
        self
    }

    /// Sets a boolean `constant`.
    pub fn flag(self, constant: Constant, on: bool) -> Self {
        self.constant(constant, on as u32)
    }

    /// Sets a float `constant`.
    pub fn float(self, constant: Constant, value: f32) -> Self {
        self.constant(constant, value.to_bits())
    }

    /// The constants one stage's shader declares, as (id, bits).
    pub fn stage_constants(&self, shader: &ShaderBinary) -> Vec<(u32, u32)> {
        let declared = shader.spec_ids();
        self.constants
            .iter()
            .map(|&(c, bits)| (c.id(), bits))
            .filter(|(id, _)| declared.contains(id))
            .collect()
    }
}

impl fmt::Display for PipelineDesc {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let shader = |s: &ShaderBinary| s.name.trim_end_matches(".spv").to_string();
        write!(f, "{} + {}", shader(self.vertex), shader(self.fragment))?;
        let mut state = Vec::new();
        if self.vertex_input == VertexInput::SceneVertices {
            state.push("scene vertices");
        }
        if self.cull_back_faces {
            state.push("back faces culled");
        }
        if self.depth_test {
            state.push("depth tested and written");
        }
        if self.depth_clamp {
            state.push("depth clamped");
        }
        if self.dynamic_stencil_reference {
            state.push("stencil reference per draw");
        }
        if !self.writes_colour {
            state.push("no colour writes");
        }
        if !state.is_empty() {
            write!(f, "; {}", state.join(", "))?;
        }
        let constants: Vec<String> = self
            .constants
            .iter()
            .map(|&(c, bits)| {
                let (_, name, kind) = c.declaration();
                match kind {
                    ConstantKind::Uint => format!("{name}={bits}"),
                    ConstantKind::Float => format!("{name}={}", f32::from_bits(bits)),
                    ConstantKind::Bool => format!("{name}={}", bits != 0),
                }
            })
            .collect();
        if !constants.is_empty() {
            write!(f, "; {}", constants.join(" "))?;
        }
        Ok(())
    }
}

/// What every step's pipeline takes from its pass and the frame: the guard band, the pass's
/// first view, the step's stencil state and, in a counting frame, its first counter slot.
pub(super) struct StepContext {
    pub counter_base: Option<u32>,
    pub guard_band: u32,
    pub first_view: u32,
    pub stencil: Option<StencilState>,
}

impl StepContext {
    /// `vertex` with `plain`, or in a counting frame with `counting` and its counter slots; the
    /// guard band's scale and the pass's first view set where the shaders declare them.
    pub fn pipeline(
        &self,
        vertex: &'static ShaderBinary,
        plain: &'static ShaderBinary,
        counting: &'static ShaderBinary,
    ) -> PipelineDesc {
        let fragment = if self.counter_base.is_some() {
            counting
        } else {
            plain
        };
        PipelineDesc {
            stencil: self.stencil,
            ..PipelineDesc::new(vertex, fragment)
        }
        .float(Constant::ClipXyScale, 1.0 / self.guard_band as f32)
        .constant(Constant::FirstView, self.first_view)
        .constant(Constant::CounterBase, self.counter_base.unwrap_or(0))
    }
}
