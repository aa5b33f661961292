use std::fmt;

use super::model::{FramePlan, PassKind, PassPlan, Submission, TargetLayout};
use super::steps::{DrawSet, Step};
use crate::mffr::MffrOrder;

pub(super) fn mib(bytes: u64) -> String {
    format!("{:.2} MiB", bytes as f64 / (1024.0 * 1024.0))
}

impl fmt::Display for FramePlan {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        self.write_header(f)?;
        self.write_effects(f)?;
        self.write_attachments(f)?;
        writeln!(f, "passes:")?;
        for p in &self.passes {
            self.write_pass(f, p)?;
            self.write_step_notes(f, p)?;
            write_pass_targets(f, self, p)?;
        }
        self.write_footer(f)
    }
}

impl FramePlan {
    /// The frame as a whole: headset, eyes, layout and each effect as resolved.
    fn write_header(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let fov = self.eyes.left_fov;
        writeln!(
            f,
            "frame plan{}: {} ({}), {} per eye, stereo {}, {} views, MSAA {}x",
            if self.engine_draws {
                " around an engine's draws"
            } else {
                ""
            },
            self.hmd.display_name,
            self.hmd.name,
            self.eye_resolution,
            self.stereo,
            self.views,
            self.samples
        )?;
        writeln!(
            f,
            "  eyes: IPD {:.1} mm, cant {:.1}°, left-eye tangents l/r/u/d {:.3}/{:.3}/{:.3}/{:.3}; depth reverse-Z, near {} far {}",
            self.eyes.ipd_m * 1000.0,
            self.eyes.cant_rad.to_degrees(),
            fov.left,
            fov.right,
            fov.up,
            fov.down,
            self.near,
            self.far
        )?;
        let tracker = match self.hmd.eye_tracker {
            None => "no eye tracker (fixed foveation only)".to_string(),
            Some(t) => format!(
                "eye-tracked (rate {}, latency {})",
                t.rate_hz
                    .map_or("unpublished".into(), |r| format!("{r} Hz")),
                t.latency_ms
                    .map_or("unpublished".into(), |l| format!("≈ {l} ms"))
            ),
        };
        writeln!(
            f,
            "  headset: panel {}x{} per eye at {} Hz, {tracker}; {:.1} px/° at the lens axis at this resolution ({})",
            self.hmd.panel_per_eye.0,
            self.hmd.panel_per_eye.1,
            self.hmd.refresh_hz,
            self.pixels_per_degree(crate::view::Eye::Left),
            self.hmd.source
        )?;
        let layout = match self.layout {
            TargetLayout::Layered => "one array layer per eye",
            TargetLayout::PerEye => "one image per eye",
            TargetLayout::SideBySide => "both eyes side by side in one image",
        };
        writeln!(
            f,
            "  layout: {layout}; about {} draw calls per frame (estimate before culling, without mask fans and probes)",
            self.draw_calls_estimate
        )?;
        Ok(())
    }

    /// Each effect as resolved for this frame.
    fn write_effects(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if let Some(g) = &self.foveation {
            writeln!(
                f,
                "  foveation: ratio {}, periphery views {} at {}x MSAA, fovea views {} at {}x, fovea {:.0} px on screen ({:.1} px inset circle), periphery hole {:.1} px, blend band {} px, stencil masks {}",
                g.ratio,
                g.periphery_view,
                g.periphery_samples(self.samples),
                g.fovea_view,
                self.samples,
                g.fovea_screen_px,
                g.fovea_circle_px,
                g.periphery_hole_px,
                g.blend_band_px,
                if g.stencil { "on" } else { "off" }
            )?;
            if let Some(density) = self.periphery_density() {
                let screen = self.eye_resolution.width;
                writeln!(f, "  periphery: {}", periphery_reason(g, density, screen))?;
            }
            if let Some(r) = g.ring {
                writeln!(f, "  parafoveal ring: {r}")?;
            }
        }
        if let Some(c) = &self.fovea_layout {
            writeln!(
                f,
                "  fovea layout: {}, fovea views {}: {}",
                c.layout,
                if c.cull {
                    "culled to their own superfrustum"
                } else {
                    "not culled"
                },
                c.reason
            )?;
        }
        if self.lit {
            let filter = match self.anisotropy {
                Some(a) => format!("anisotropic (up to {a}x)"),
                None => "trilinear".to_string(),
            };
            writeln!(
                f,
                "  shading: lit PBR materials (base colour, normal, occlusion-roughness-metallic textures with full mips, {filter}), sun, {} point light{} (a constant of the pipelines) and sky",
                self.point_lights,
                if self.point_lights == 1 { "" } else { "s" }
            )?;
            if self.alpha_mask {
                writeln!(
                    f,
                    "  alpha-masked materials: the scene shader discards below the cutoff and tests depth late"
                )?;
            }
        }
        if let Some(l) = &self.lens {
            let d = l.display[0];
            writeln!(
                f,
                "  output for the lens: radial distortion k1 {} k2 {} (tangent units); left display tangents l/r/u/d {:.3}/{:.3}/{:.3}/{:.3} show the rendered field's edges",
                l.distortion.k1, l.distortion.k2, d.left, d.right, d.up, d.down
            )?;
        }

        self.write_hmd_mask(f)?;
        if let Some(m) = &self.mffr {
            writeln!(
                f,
                "  MFFR {}: split {:.2} m ({} → {:.2} px disparity there), far view {} at {}x MSAA and {} the eyes' pixel density covering both eyes (tangents l/r/u/d {:.3}/{:.3}/{:.3}/{:.3}), far pass near {:.2} m",
                m.config.name(),
                m.split_m,
                m.config.split,
                m.disparity_at_split_px,
                m.resolution,
                m.config.far_msaa.unwrap_or(self.samples),
                m.config.far_density,
                m.far_fov.left,
                m.far_fov.right,
                m.far_fov.up,
                m.far_fov.down,
                m.far_near
            )?;
        }
        if let Some(c) = &self.culling {
            writeln!(
                f,
                "  culling: {} on the CPU each frame, draw distance {} (chunk grid + octree)",
                c.strategy.name(),
                c.draw_distance
            )?;
        }
        if let Some(c) = &self.clusters {
            let how = c.drawn_whole.map_or(
                "culled per draw set against its own frustum, reach and back-face cones".into(),
                |why| format!("drawn whole: {why}"),
            );
            writeln!(
                f,
                "  clusters: {} in {} meshes (at most {} triangles each), {how}",
                c.clusters, c.meshes, c.max_triangles
            )?;
        }
        if let Some(l) = &self.lod {
            writeln!(
                f,
                "  level of detail: {} simplified levels in {} meshes; each draw set draws, per instance, the coarsest whose measured error projects within {} px in every view that draws it",
                l.levels, l.meshes, l.max_error_px
            )?;
        }
        Ok(())
    }

    /// The HMD stencil mask: a runtime's hidden-area mesh, or the profile's analytic ellipse.
    fn write_hmd_mask(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.hidden_area_mesh {
            writeln!(
                f,
                "  HMD stencil mask: the runtime's hidden-area mesh, handed in per frame (at most {} triangles per eye); the profile's ellipse would hide {}",
                crate::view::MAX_HIDDEN_TRIANGLES,
                self.hmd_mask.iter().flatten().map(|r| format!("{:.1} %", 100.0 * r.hidden_fraction())).collect::<Vec<_>>().join(" / ")
            )?;
        } else if let Some(regions) = &self.hmd_mask {
            let hidden: Vec<String> = regions
                .iter()
                .map(|r| format!("{:.1} %", 100.0 * r.hidden_fraction()))
                .collect();
            let source = if self.hmd.hidden_area_fraction.is_some() {
                "ellipse matching the headset's hidden-area mesh area"
            } else {
                "circular fallback: no published hidden-area mesh"
            };
            writeln!(
                f,
                "  HMD stencil mask: hides {} of each eye (analytic; {source}; `foveate pixels` measures it)",
                hidden.join(" / ")
            )?;
        }
        Ok(())
    }

    /// A pass: its views and submission, what it samples, its steps and their pipelines.
    fn write_pass(&self, f: &mut fmt::Formatter<'_>, p: &PassPlan) -> fmt::Result {
        let submission = match p.submission {
            _ if p.kind == PassKind::LayerCopy => {
                "a full-view triangle into one layer, copying the image it samples".to_string()
            }
            _ if p.kind.is_full_view() => {
                "a full-view triangle per eye, sampling the views".to_string()
            }
            Submission::Multiview if p.view_mask == 0b1 => {
                "one view, a pass of its own: this driver draws what a multiview pass clips with the first view's data"
                    .to_string()
            }
            Submission::Multiview => "scene once, broadcast by multiview".to_string(),
            Submission::SingleEye(eye) => format!("scene once for the {eye:?} eye").to_lowercase(),
            Submission::PerObject => "each object twice, view state switched".to_string(),
            Submission::Instanced => {
                "instance count doubled, clip-space half viewports".to_string()
            }
            Submission::FarView => "the far field once, from the far view".to_string(),
        };
        let first_view = if p.first_view > 0 {
            format!(" (views {}..)", p.first_view)
        } else {
            String::new()
        };
        writeln!(
            f,
            "  {} — view mask {:#04b}{first_view}; {submission}",
            p.name, p.view_mask
        )?;
        for &id in &p.samples {
            writeln!(
                f,
                "    samples #{id} ({}) as a texture",
                self.attachments[id].name
            )?;
        }
        let steps: Vec<String> = p.steps.iter().map(ToString::to_string).collect();
        writeln!(f, "    steps: {}", steps.join(" → "))?;
        for (step, pipeline) in p.steps.iter().zip(&p.pipelines) {
            let name = step.counted().name();
            match step {
                Step::Scene { stencil, .. } if self.engine_draws => writeln!(
                    f,
                    "    {name} pipeline: the engine's own, made for this pass's render pass; {}; depth reverse-Z, tested (greater) and written",
                    stencil.map_or("no stencil test".to_string(), |s| s.to_string())
                )?,
                _ => writeln!(f, "    {name} pipeline: {pipeline}")?,
            }
        }
        Ok(())
    }

    /// What each step of a pass does, in words.
    fn write_step_notes(&self, f: &mut fmt::Formatter<'_>, p: &PassPlan) -> fmt::Result {
        for step in &p.steps {
            match step {
                Step::MaskFans { hidden_area, .. } => {
                    let mut masks = Vec::new();
                    if *hidden_area {
                        masks.push("everything but the runtime's hidden-area mesh in the eye (periphery) views");
                    } else if self.hmd_mask.is_some() {
                        masks.push("the lens-visible ellipse in the eye (periphery) views");
                    }
                    if self.foveation.is_some_and(|g| g.stencil) {
                        masks.push(
                            "inset circle in the fovea views, outset (hole) in the periphery views",
                        );
                    }
                    writeln!(f, "    stencil masks first: {}", masks.join("; "))?;
                }
                Step::Scene { .. } if self.engine_draws => writeln!(
                    f,
                    "    the engine draws its world into the pass's views (culled against the pass's superfrustum)"
                )?,
                Step::Scene { draw_set, .. } => match draw_set {
                    DrawSet::All => {}
                    DrawSet::Visible => writeln!(
                        f,
                        "    draws the instances its views may see (culled per frame: {})",
                        self.culling.map_or("", |c| c.strategy.name())
                    )?,
                    DrawSet::VisibleToEye(eye) => writeln!(
                        f,
                        "    draws the instances the {} eye's frustum keeps (culled per frame for this eye alone)",
                        eye.name()
                    )?,
                    DrawSet::NearField => writeln!(
                        f,
                        "    draws the near field (instances in front of the split, culled per frame)"
                    )?,
                    DrawSet::FarField => writeln!(
                        f,
                        "    draws the far field (instances beyond the split, culled per frame)"
                    )?,
                    DrawSet::Fovea => writeln!(
                        f,
                        "    draws the instances the fovea views' superfrustum keeps (culled per frame)"
                    )?,
                    DrawSet::FoveaTagged => writeln!(
                        f,
                        "    draws the periphery's instances, each tagged per frame with whether the fovea superfrustum keeps it; untagged ones emit no primitives in the fovea views"
                    )?,
                },
                Step::FarComposite { .. } => match p.far_composite() {
                    Some(MffrOrder::FarFirst) => writeln!(f, "    far image composited first into every pixel, near field drawn over it")?,
                    _ => writeln!(f, "    near field first, marking stencil; far image composited into the unmarked pixels")?,
                },
                Step::Probe { .. } => writeln!(
                    f,
                    "    coverage probe last: a full-view draw per view, counted"
                )?,
                Step::RadialMask { .. } => {
                    if let Some(r) = &self.radial_density {
                        writeln!(
                            f,
                            "    radial density mask: 2x2 quads skipped past {} of the lens radius (every other), past {} (three in four); reconstructed after the pass",
                            r.config.inner, r.config.outer
                        )?;
                    }
                }
                Step::Output(o) if o.temporal => {
                    if let Some(t) = self.foveation.and_then(|f| f.temporal) {
                        writeln!(
                            f,
                            "    periphery jittered over a {}-frame Halton cycle, accumulated here: the history reprojected by depth and read {} where the point moved (dropped where the frame before's periphery depth differs by over 10 %: in the texel it lay in where it moved, in any of the 2x2 around it where it did not), clipped to the periphery's {} in YCoCg ({}), {} blended in (weight {}; {} where nothing moved); over the periphery's hole what the fovea showed, reset at cuts (> {} m, > {}°){}",
                            t.jitter_cycle, filter_words(t.filter), neighbourhood_words(t.neighbourhood), clip_words(t.clip), new_sample_words(t.new_sample), t.blend, t.still_blend, t.cut_distance_m, t.cut_angle_deg,
                            t.within_deg.map_or(String::new(), |d| format!("; only within {d}° of the fovea's centre, each frame's periphery beyond (no history read there)"))
                        )?;
                    }
                    if let (Some(h), Some(d)) = (self.history, self.depth_history) {
                        writeln!(
                            f,
                            "    history: #{} and #{} swap roles every frame (no copy), and so do the periphery's depths #{} and #{}",
                            h.read, h.written, d.written, d.read
                        )?;
                    }
                }
                Step::Output(_) | Step::Reconstruct | Step::LayerCopy { .. } => {}
            }
        }
        Ok(())
    }

    /// Fragment counting, queries, effect buffers, memory and traffic.
    fn write_footer(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if !self.counted.is_empty() {
            let steps: Vec<String> = self
                .counted
                .iter()
                .map(|c| format!("{} ({})", c.step.name(), self.passes[c.pass].name))
                .collect();
            writeln!(
                f,
                "fragment counting (a counting frame, never timed): {}",
                steps.join(", ")
            )?;
        }
        if self.timestamp_queries + self.statistics_queries > 0 {
            let mut pools = Vec::new();
            if self.timestamp_queries > 0 {
                pools.push(format!("{} timestamps", self.timestamp_queries));
            }
            if self.statistics_queries > 0 {
                pools.push(format!("{} pipeline statistics", self.statistics_queries));
            }
            let spare = if self.query_spare_slots > 0 {
                let slots = if self.query_spare_slots == 1 {
                    "slot"
                } else {
                    "slots"
                };
                format!(
                    ", each pool with {} spare {slots} (this driver writes a query after a multiview pass into one slot per view)",
                    self.query_spare_slots
                )
            } else {
                String::new()
            };
            writeln!(f, "queries per frame: {}{spare}", pools.join(", "))?;
        }
        writeln!(
            f,
            "frame slots: {} (frames in flight; each slot its own uniforms, descriptor sets and query pools)",
            self.frame_slots
        )?;
        if self.spare_instances > 0 {
            writeln!(
                f,
                "spare instances: {} per mesh (absent until added; {} instances in the buffers)",
                self.spare_instances, self.scene_instances
            )?;
        }
        if !self.buffers.is_empty() {
            writeln!(f, "effect buffers:")?;
            for b in &self.buffers {
                writeln!(f, "  {} ({} bytes)", b.name, b.bytes)?;
            }
        }
        writeln!(
            f,
            "memory: {} resident, {} transient (on tile where the device offers lazily allocated memory)",
            mib(self.resident_bytes()),
            mib(self.transient_bytes())
        )?;
        write!(
            f,
            "estimated external traffic per frame (tile GPU): {} (attachment loads + stores + sampling + output readback: the attachments' last four columns, summed)",
            mib(self.external_traffic_bytes())
        )
    }
}

/// A pass's workarounds, attachment uses (ops, layouts, clears) and barriers.
fn write_pass_targets(f: &mut fmt::Formatter<'_>, plan: &FramePlan, p: &PassPlan) -> fmt::Result {
    if p.depth_clamp {
        writeln!(
            f,
            "    depth clamp, not clipping, ends the near field at the split (same driver quirk)"
        )?;
    }
    if p.guard_band > 1 {
        writeln!(
                f,
                "    guard band x{} (works around this driver clipping multiview primitives into view 0)",
                p.guard_band
            )?;
    }
    for (what, u) in [
        ("colour", Some(&p.color)),
        ("depth", p.depth.as_ref()),
        ("resolve", p.resolve.as_ref()),
        ("history", p.history.as_ref()),
        ("depth resolve (sample 0)", p.depth_resolve.as_ref()),
    ] {
        let Some(u) = u else { continue };
        let stencil = match plan.attachments[u.attachment]
            .format
            .stencil_bytes_per_pixel()
        {
            0 => String::new(),
            _ => format!(" (stencil {})", u.stencil_store),
        };
        writeln!(
            f,
            "    {what:<7} #{} layers {}..{}: load {}, store {}{stencil}",
            u.attachment,
            u.base_layer,
            u.base_layer + u.layer_count,
            u.load,
            u.store
        )?;
        let clear = u
            .clear
            .map_or(String::new(), |c| format!("; clears to {c}"));
        writeln!(
            f,
            "            layout {} → {}{clear}",
            u.initial_layout, u.final_layout
        )?;
    }
    for (what, barriers) in [
        ("waits on", &p.barriers.wait),
        ("signals", &p.barriers.signal),
    ] {
        let list: Vec<String> = barriers.iter().map(ToString::to_string).collect();
        writeln!(f, "    {what}: {}", list.join("; "))?;
    }
    Ok(())
}

/// How the plan's printout names a history clip.
fn filter_words(filter: crate::foveation::HistoryFilter) -> &'static str {
    match filter {
        crate::foveation::HistoryFilter::Bilinear => "bilinearly",
        crate::foveation::HistoryFilter::CatmullRom => {
            "with Catmull-Rom over 4x4 texels (within the 2x2's range)"
        }
    }
}

fn neighbourhood_words(neighbourhood: crate::foveation::ClipNeighbourhood) -> &'static str {
    match neighbourhood {
        crate::foveation::ClipNeighbourhood::Square => "3x3 neighbourhood",
        crate::foveation::ClipNeighbourhood::Cross => {
            "cross of five texels (the texel and its edge neighbours)"
        }
    }
}

fn new_sample_words(new_sample: crate::foveation::NewSample) -> &'static str {
    match new_sample {
        crate::foveation::NewSample::Nearest => "the nearest periphery texel",
        crate::foveation::NewSample::Weighted => {
            "the periphery's 3x3 texels, each weighted by its distance, where the point moved \
             (the nearest texel elsewhere),"
        }
    }
}

fn clip_words(clip: crate::foveation::HistoryClip) -> String {
    match clip {
        crate::foveation::HistoryClip::Variance { sigmas } => {
            format!("variance clipping, ±{sigmas} standard deviations")
        }
        crate::foveation::HistoryClip::Range => "its min/max box".to_string(),
        crate::foveation::HistoryClip::Moved => {
            "its min/max box where the head's motion moved the point or an instance that moves \
             lies, elsewhere not clipped"
                .to_string()
        }
        crate::foveation::HistoryClip::DepthOnly => {
            "not clipped: moving surfaces trail".to_string()
        }
        crate::foveation::HistoryClip::Off => "not clipped: trails".to_string(),
    }
}

/// Why the periphery is made the way it is: what each choice trades, in words. The figures
/// behind them are measurements on one scene and panel (BENCHMARKS.md), so a plan names no
/// measured figure, and says "measured" where a verdict is one.
fn periphery_reason(g: &crate::foveation::FoveationGeometry, density: f64, screen: u32) -> String {
    use crate::foveation::{HistoryAt, HistoryFormat, RECOMMENDED_PERIPHERY_DENSITY};
    let prefiltered = match g.periphery_prefilter {
        true => {
            ", its highlights prefiltered to the screen's (measured to lose, still and walking)"
        }
        false => "",
    };
    match g.temporal {
        None => format!(
            "one frame at {density:.2} of the screen's density{prefiltered}, upscaled, nothing kept between frames: the cheapest foveated frame, no history to read or write, nothing that changes while the head is still, but it measured less accurate than stereo without MSAA over the frame (eFLIP p99) in every motion on the lit atrium at the Quest Pro's panel; the library's default accumulates it instead, at {RECOMMENDED_PERIPHERY_DENSITY} of the screen's density, for more time and a history's bytes (BENCHMARKS.md)"
        ),
        Some(t) => {
            let history = match (t.history_at, t.history_density) {
                (HistoryAt::Output, _) => "a history at the output's pixels".to_string(),
                (HistoryAt::Periphery, None) => {
                    "a history at the periphery's own texels".to_string()
                }
                (HistoryAt::Periphery, Some(d)) => format!(
                    "a history at {d:.2} of the screen's density, in a pass of its own"
                ),
            };
            // The recommended density, up to the rounding of the views to whole pixels.
            let off_px = (density - f64::from(RECOMMENDED_PERIPHERY_DENSITY)).abs() * f64::from(screen);
            let recommended = off_px <= 0.5 + 1e-3
                && t.history_at == HistoryAt::Output
                && t.history_format == HistoryFormat::Colour;
            let history = match t.history_format {
                HistoryFormat::Colour => history,
                HistoryFormat::Luma => history + ", its luma alone in a byte",
            };
            let verdict = if recommended {
                "; this is the library's default: the cheapest configuration measured at least as accurate as stereo without MSAA over the frame (eFLIP p99) with the head still, walking and through both saccade traces, at both gazes, on the lit atrium at the Quest Pro's panel (single frames at the fovea's ratio lost in every motion and those as accurate cost more, the history at the periphery's texels lost one walk)"
            } else {
                ""
            };
            format!(
                "accumulated over jittered frames at {density:.2} of the screen's density: sharper than one frame at that density, for {history} read and written every frame (its bytes below) and a faint shimmer with the head still; while the head moves it measured to flicker more than stereo without MSAA at every density tried{verdict} (BENCHMARKS.md)"
            )
        }
    }
}
