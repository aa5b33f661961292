//! Temporal accumulation of the periphery (Di Donato 2017 §3.6; the technique of TAA and its
//! upsampling variants: Yang, Nehab & Sander 2009, "Amortized supersampling"; Karis 2014,
//! "High quality temporal supersampling"): each frame the periphery views are shifted by a
//! sub-pixel offset from a Halton sequence, and the output pass's periphery comes from a history
//! at the screen's density that gathers those samples over frames. The pure part lives here: the
//! jitter sequence, its settings, and when a head movement is a cut that drops the history.

use glam::{Mat4, Vec2};

use super::history::{HistoryAt, HistoryFormat};
use crate::vocab::ConfigError;

/// What a user chooses about the periphery's temporal accumulation.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TemporalConfig {
    /// The weight a fully trusted new sample gets against the history (an exponential moving
    /// average: about `2 / blend − 1` frames remembered). 1 keeps no history.
    pub blend: f32,
    /// The same weight where nothing moved: the head's motion moved the point less than a
    /// tenth of a periphery texel and no instance that moves lies near it (instances are
    /// marked only under [`HistoryClip::Moved`]; under the other clips the head's motion
    /// alone decides). There the history
    /// needs no quick correction, and the jitter's shimmer, which scales with the weight, is
    /// all a new sample can add.
    pub still_blend: f32,
    /// Frames in the jitter cycle (Halton 2, 3); 1 renders every frame at the pixel centres.
    pub jitter_cycle: u32,
    /// A head that moves farther than this between frames (metres) is a cut: the history is
    /// dropped instead of reprojected.
    pub cut_distance_m: f32,
    /// Likewise for a head that turns more than this between frames (degrees).
    pub cut_angle_deg: f32,
    /// How the reprojected history is kept from straying from what the periphery shows now.
    pub clip: HistoryClip,
    /// How the history is resampled where the head's motion moved the point.
    pub filter: HistoryFilter,
    /// Which periphery texels around the pixel make the box the clip holds the history to.
    pub neighbourhood: ClipNeighbourhood,
    /// What of this frame's periphery is blended into the history at a pixel.
    pub new_sample: NewSample,
    /// Where the history's pixels lie: the output's or the periphery's own texels.
    pub history_at: HistoryAt,
    /// With [`HistoryAt::Periphery`]: the history's density, of the screen's pixels per side,
    /// in place of the periphery's own (finer texels blur less each time the history is
    /// resampled and keep more of the jitter's sub-texel detail, for more pixels accumulated).
    /// `None`: the periphery's density.
    pub history_density: Option<f32>,
    /// What the history keeps of a pixel: its colour, or its luma alone in a byte.
    pub history_format: HistoryFormat,
    /// How far from the gaze the periphery accumulates: within this eccentricity (degrees,
    /// from the fovea's centre) it accumulates, beyond it each frame's periphery is shown as it
    /// is (the jitter undone) and its pixels read no history and do none of the accumulation's
    /// work; across the last [`REACH_EDGE_DEG`] the two blend. `None`: everywhere.
    pub within_deg: Option<f32>,
}

/// The band at the edge of [`TemporalConfig::within_deg`] over which the accumulated
/// periphery blends into the single frame (degrees, smoothstep), so no seam shows.
pub const REACH_EDGE_DEG: f32 = 5.0;

/// What of this frame's periphery enters the history at a pixel, each periphery texel weighted
/// by `exp(−2d²)`, `d` its distance from the pixel's centre in screen pixels (Yang, Nehab &
/// Sander 2009's sample weight), the history's weight falling as theirs sum up to one.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum NewSample {
    /// The nearest texel alone: one read. As the head turns, which texel is nearest switches
    /// from frame to frame and its colour enters at once: the walk's periphery flickers more.
    Nearest,
    /// Where the head's motion moved the point, the 3×3 texels around the pixel, so what
    /// enters changes smoothly as the texels move past; taken from the reads the clip's box
    /// makes there, so it costs nine weights, not nine more reads. Where nothing moved, the
    /// nearest texel (a still frame is the nearest's to the bit). Measured along the walk at
    /// half the Quest Pro's panel (lavapipe, side by side): in the periphery, flicker 2 % lower
    /// than the nearest's with the periphery at 0.6 and 20 % lower at the screen's density,
    /// eFLIP p99 2 % lower at both; no time measurable at 0.6, 3 % of the frame at the
    /// screen's density; at the fovea layout's own density (texels over two pixels apart) the
    /// same figures for 2–5 %. At the panel itself, at 0.6: the walk's p99 and flicker 2–3 %
    /// lower at both gazes, the still frame and the saccade trace unchanged, the walk's frame
    /// 2–6 % slower (docs/notebook/2026-11-28-every-neighbour-as-a-new-sample.md).
    Weighted,
}

impl std::fmt::Display for NewSample {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            NewSample::Nearest => "nearest",
            NewSample::Weighted => "weighted",
        })
    }
}

impl std::str::FromStr for NewSample {
    type Err = ConfigError;

    /// `nearest` or `weighted`.
    fn from_str(s: &str) -> Result<Self, ConfigError> {
        match s {
            "nearest" => Ok(NewSample::Nearest),
            "weighted" => Ok(NewSample::Weighted),
            _ => Err(ConfigError::new("new sample", s, "nearest or weighted")),
        }
    }
}

/// The periphery texels around a pixel whose colours make the box its history is clipped to
/// (and in which a moving instance is looked for).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ClipNeighbourhood {
    /// The 3×3 texels around it: nine reads.
    Square,
    /// The texel and its four edge neighbours: five reads. Measured at the Quest Pro's panel
    /// (lavapipe): 5–6 % off the frame; along a walk the same eFLIP p99 and 4 % more flicker
    /// (its box, from fewer colours, is narrower and clips more); with the head still the same
    /// figures, since the `Moved` clip uses no box where nothing moved
    /// (docs/notebook/2026-11-28-h100-density-and-samples.md, "A neighbourhood of five reads").
    Cross,
}

impl std::fmt::Display for ClipNeighbourhood {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            ClipNeighbourhood::Square => "3x3",
            ClipNeighbourhood::Cross => "cross",
        })
    }
}

impl std::str::FromStr for ClipNeighbourhood {
    type Err = ConfigError;

    /// `3x3` or `cross`.
    fn from_str(s: &str) -> Result<Self, ConfigError> {
        match s {
            "3x3" => Ok(ClipNeighbourhood::Square),
            "cross" => Ok(ClipNeighbourhood::Cross),
            _ => Err(ConfigError::new("clip neighbourhood", s, "3x3 or cross")),
        }
    }
}

/// How the history is read where the point moved since the frame before, and so lies between
/// the history's pixels (where nothing moved it lies on one, and every filter reads that one).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum HistoryFilter {
    /// The 2×2 pixels around the point, weighted by distance: resampled every frame of a
    /// motion, the history blurs.
    Bilinear,
    /// Catmull-Rom over the 4×4 pixels around it (Karis 2014, "High quality temporal
    /// supersampling"), held within the 2×2's range so its negative lobes cannot ring;
    /// bilinear where any of the 16 holds nothing. Sharper, and four times the reads (16 to 4).
    CatmullRom,
}

impl std::fmt::Display for HistoryFilter {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            HistoryFilter::Bilinear => "bilinear",
            HistoryFilter::CatmullRom => "catmull-rom",
        })
    }
}

impl std::str::FromStr for HistoryFilter {
    type Err = ConfigError;

    /// `bilinear` or `catmull-rom`.
    fn from_str(s: &str) -> Result<Self, ConfigError> {
        match s {
            "bilinear" => Ok(HistoryFilter::Bilinear),
            "catmull-rom" => Ok(HistoryFilter::CatmullRom),
            _ => Err(ConfigError::new(
                "history filter",
                s,
                "bilinear or catmull-rom",
            )),
        }
    }
}

/// How the reprojected history is held to the periphery's neighbourhood around the pixel
/// ([`ClipNeighbourhood`], in YCoCg) before the new sample is blended in: what stops a surface
/// that moved, changed or was uncovered from leaving a trail.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum HistoryClip {
    /// Variance clipping (Salvi 2016, "An excursion in temporal supersampling"): moved along
    /// the line to the neighbourhood's mean into the box of ± `sigmas` standard deviations
    /// around it, within the neighbourhood's range.
    Variance {
        /** The box's half-size, in standard deviations (Salvi: 1). */
        sigmas: f32,
    },
    /// Moved into the neighbourhood's range (its min/max box) along the line to its centre.
    Range,
    /// The range's clip only where something moved: where the head's motion moved the point
    /// on screen (by a tenth of a periphery texel or more), and where an instance the renderer
    /// moved or added (`Renderer::move_instance`, `Renderer::add_instance`) lies in the
    /// periphery's 3×3 neighbourhood now or lay under the history the frame before (its
    /// pixels are marked in the scene pass's alpha and the history's). Elsewhere the depth
    /// test alone. With the head still the clip pulls back detail the jitter gathered, and
    /// makes the shimmer; in motion it holds what reprojection blurs, and the reprojection
    /// follows the head alone, so only the clip holds an instance that moves. A surface that
    /// moves without the renderer knowing (a vertex animation, a changing light) keeps its
    /// trail with the head still.
    Moved,
    /// Not clipped, only tested against the frame before's depth (dropped where another
    /// surface lay there). A surface that moves on its own keeps its trail; with the head
    /// still, detail the jitter gathered is kept that a clip pulls back. To measure what the
    /// clip costs and what it holds.
    DepthOnly,
    /// Not held at all — neither clipped nor tested against the frame before's depth: a
    /// moving surface leaves a trail. To show what the two prevent.
    Off,
}

impl std::fmt::Display for HistoryClip {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            HistoryClip::Variance { sigmas } => write!(f, "variance:{sigmas}"),
            HistoryClip::Range => f.write_str("range"),
            HistoryClip::Moved => f.write_str("moved"),
            HistoryClip::DepthOnly => f.write_str("depth"),
            HistoryClip::Off => f.write_str("off"),
        }
    }
}

impl std::str::FromStr for HistoryClip {
    type Err = ConfigError;

    /// `variance` (1 standard deviation), `variance:SIGMAS`, `range`, `moved`, `depth` or `off`.
    fn from_str(s: &str) -> Result<Self, ConfigError> {
        let clip = match s.split_once(':') {
            None if s == "variance" => HistoryClip::Variance { sigmas: 1.0 },
            None if s == "range" => HistoryClip::Range,
            None if s == "moved" => HistoryClip::Moved,
            None if s == "depth" => HistoryClip::DepthOnly,
            None if s == "off" => HistoryClip::Off,
            Some(("variance", sigmas)) => HistoryClip::Variance {
                sigmas: sigmas.parse().map_err(|_| {
                    ConfigError::new("clip", s, "variance:SIGMAS with SIGMAS a number")
                })?,
            },
            _ => {
                return Err(ConfigError::new(
                    "clip",
                    s,
                    "variance, variance:SIGMAS, range, moved, depth or off",
                ))
            }
        };
        Ok(clip)
    }
}

impl HistoryClip {
    /// The shader's encoding (`accumulate.glsl`'s `c.clip.x`): the box's half-size in standard
    /// deviations; a huge one for the range alone; negative for no clip.
    pub(crate) fn spread(self) -> f32 {
        match self {
            HistoryClip::Variance { sigmas } => sigmas,
            HistoryClip::Range | HistoryClip::Moved => 1e30,
            HistoryClip::DepthOnly | HistoryClip::Off => -1.0,
        }
    }

    /// The shader's `c.clip.y`: 0 no depth test, 1 the depth test, 2 the depth test and the
    /// clip only where the point moved.
    pub(crate) fn depth_test(self) -> f32 {
        match self {
            HistoryClip::Off => 0.0,
            HistoryClip::Moved => 2.0,
            _ => 1.0,
        }
    }
}

impl Default for TemporalConfig {
    fn default() -> Self {
        TemporalConfig {
            // A history resampled every frame blurs with each resample it keeps. Along the walk
            // at the Quest Pro's panel 0.35 had the least flicker of ⅛, ¼, 0.35, ½ and 1
            // (0.00241 against ⅛'s 0.00262) and an eFLIP p99 within 3 % of the best (0.0534
            // against ⅛'s 0.0604) (docs/notebook/2026-11-26-accumulation-in-the-output-pass.md, "A faster blend").
            blend: 0.35,
            // Keeps the jitter's shimmer with the head still within the ≤ 0.0003 asked at the
            // Quest Pro's panel, at both gazes and the periphery at 0.5 and 0.6 (0.00022–0.00028;
            // ⅟16 let 0.6 reach 0.00034), for under 2 % of that frame's eFLIP p99
            // (docs/notebook/2026-11-26-accumulation-in-the-output-pass.md, "The density the
            // walk needs").
            still_blend: 0.05,
            jitter_cycle: 8,
            // A head moves ≈ 2 m/s and turns ≈ 300°/s at most: 90 Hz frames stay well inside.
            cut_distance_m: 0.5,
            cut_angle_deg: 30.0,
            // The most accurate in every motion measured, and no slower
            // (docs/notebook/2026-11-26-accumulation-in-the-output-pass.md).
            clip: HistoryClip::Moved,
            filter: HistoryFilter::Bilinear,
            // The cross is faster but flickers more along a walk, and no GPU has timed it yet.
            neighbourhood: ClipNeighbourhood::Square,
            // The weighted sample's gain at the recommended density 0.6 holds at the panel
            // (2–3 % in the walk's p99 and flicker, both gazes), but it costs 2–6 % of the
            // walk's frame there in four runs, two of them side by side within 1 %, and the
            // default was to cost no measurable time
            // (docs/notebook/2026-11-28-every-neighbour-as-a-new-sample.md).
            new_sample: NewSample::Nearest,
            history_at: HistoryAt::Output,
            history_density: None,
            history_format: HistoryFormat::Colour,
            within_deg: None,
        }
    }
}

impl TemporalConfig {
    /// Checks every field against its range; the error names the first out of it.
    pub fn validate(&self) -> Result<(), ConfigError> {
        for (field, value) in [
            ("temporal_blend", self.blend),
            ("temporal_still_blend", self.still_blend),
        ] {
            if !(value > 0.0 && value <= 1.0) {
                return Err(ConfigError::new(field, value, "0 < blend ≤ 1"));
            }
        }
        if !(1..=256).contains(&self.jitter_cycle) {
            return Err(ConfigError::new(
                "jitter_cycle",
                self.jitter_cycle,
                "1..=256 frames",
            ));
        }
        if let HistoryClip::Variance { sigmas } = self.clip {
            if !(sigmas > 0.0 && sigmas.is_finite()) {
                return Err(ConfigError::new(
                    "clip sigmas",
                    sigmas,
                    "> 0 and finite (HistoryClip::Range for the range alone)",
                ));
            }
        }
        if let Some(density) = self.history_density {
            if self.history_at != HistoryAt::Periphery {
                return Err(ConfigError::new(
                    "temporal_history_density",
                    density,
                    "only with the history in a pass of its own (history_at: periphery)",
                ));
            }
            if !(density > 0.0 && density <= 1.0) {
                return Err(ConfigError::new(
                    "temporal_history_density",
                    density,
                    "0 < density ≤ 1 (of the screen's pixels per side)",
                ));
            }
        }
        if let Some(within) = self.within_deg {
            if !(within > 0.0 && within <= 180.0) {
                return Err(ConfigError::new(
                    "temporal_within_deg",
                    within,
                    "0 < degrees ≤ 180 (None: everywhere)",
                ));
            }
        }
        // Infinity is allowed: it turns cut detection off.
        for (field, value) in [
            ("cut_distance_m", self.cut_distance_m),
            ("cut_angle_deg", self.cut_angle_deg),
        ] {
            if value.is_nan() || value <= 0.0 {
                return Err(ConfigError::new(field, value, "> 0 (infinity: never)"));
            }
        }
        Ok(())
    }

    /// Frame `frame`'s sub-pixel offset of the periphery views, in periphery pixels (x right,
    /// y down), each axis in (−½, ½): the Halton (2, 3) point of the frame's place in the cycle.
    pub fn jitter(&self, frame: u64) -> Vec2 {
        if self.jitter_cycle == 1 {
            return Vec2::ZERO;
        }
        // Index 0 of Halton is (0, 0): start at 1 so every point of the cycle is interior.
        let i = frame % self.jitter_cycle as u64 + 1;
        Vec2::new(halton(i, 2) - 0.5, halton(i, 3) - 0.5)
    }

    /// The cosines of the eccentricities where the accumulation ends and where it starts to
    /// fade (`accumulate.glsl`'s `c.still.yz`): below the first a pixel does none of its work.
    /// Accumulating everywhere, values no direction reaches (< −1).
    pub(crate) fn reach_cosines(&self) -> (f32, f32) {
        match self.within_deg {
            None => (-3.0, -2.0),
            Some(within) => (
                within.to_radians().cos(),
                (within - REACH_EDGE_DEG).max(0.0).to_radians().cos(),
            ),
        }
    }

    /// Whether the head's move from `previous` to `current` (world from eye) is a cut.
    pub fn is_cut(&self, previous: Mat4, current: Mat4) -> bool {
        let moved = (current.w_axis - previous.w_axis).truncate().length();
        let forward = |m: Mat4| m.z_axis.truncate().normalize_or_zero();
        let turned = forward(previous)
            .dot(forward(current))
            .clamp(-1.0, 1.0)
            .acos()
            .to_degrees();
        moved > self.cut_distance_m || turned > self.cut_angle_deg
    }
}

/// The radical inverse of `index` in `base`: the Halton sequence's coordinate.
pub fn halton(mut index: u64, base: u64) -> f32 {
    let (mut result, mut scale) = (0.0f64, 1.0f64);
    while index > 0 {
        scale /= base as f64;
        result += scale * (index % base) as f64;
        index /= base;
    }
    result as f32
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    /// Halton's first points, from its definition (digits mirrored about the point).
    #[test]
    fn halton_matches_its_definition() {
        let base2 = [0.5, 0.25, 0.75, 0.125, 0.625, 0.375, 0.875];
        let base3 = [1.0 / 3.0, 2.0 / 3.0, 1.0 / 9.0, 4.0 / 9.0, 7.0 / 9.0];
        for (i, &h) in base2.iter().enumerate() {
            assert_eq!(halton(i as u64 + 1, 2), h);
        }
        for (i, &h) in base3.iter().enumerate() {
            assert!((halton(i as u64 + 1, 3) - h as f32).abs() < 1e-7);
        }
    }

    /// The cycle's offsets are distinct, inside the pixel, and centred: over a cycle their mean
    /// is within a sixteenth of a pixel of the centre (a biased sequence would shift the image).
    #[test]
    fn jitter_covers_the_pixel_around_its_centre() {
        let t = TemporalConfig::default();
        let points: Vec<Vec2> = (0..t.jitter_cycle as u64).map(|f| t.jitter(f)).collect();
        for (i, p) in points.iter().enumerate() {
            assert!(p.x.abs() < 0.5 && p.y.abs() < 0.5, "{p}");
            assert!(points[..i].iter().all(|q| q != p), "repeated {p}");
        }
        let mean = points.iter().copied().sum::<Vec2>() / points.len() as f32;
        assert!(mean.length() < 1.0 / 16.0, "mean {mean}");
        assert_eq!(t.jitter(3), t.jitter(3 + t.jitter_cycle as u64));
        let still = TemporalConfig {
            jitter_cycle: 1,
            ..t
        };
        assert_eq!(still.jitter(5), Vec2::ZERO);
    }

    #[test]
    fn a_teleport_is_a_cut_and_a_frame_of_walking_is_not() {
        let t = TemporalConfig::default();
        let at = |x: f32, yaw_deg: f32| {
            Mat4::from_translation(Vec3::new(x, 1.6, 0.0))
                * Mat4::from_rotation_y(yaw_deg.to_radians())
        };
        assert!(
            !t.is_cut(at(0.0, 0.0), at(0.02, 3.0)),
            "a 90 Hz frame of walking"
        );
        assert!(t.is_cut(at(0.0, 0.0), at(3.0, 0.0)), "teleport");
        assert!(t.is_cut(at(0.0, 0.0), at(0.0, 90.0)), "snap turn");
        let never = TemporalConfig {
            cut_distance_m: f32::INFINITY,
            cut_angle_deg: f32::INFINITY,
            ..t
        };
        assert!(!never.is_cut(at(0.0, 0.0), at(3.0, 90.0)));
        assert!(TemporalConfig { blend: 0.0, ..t }.validate().is_err());
        let still = TemporalConfig {
            still_blend: 1.5,
            ..t
        };
        assert!(still
            .validate()
            .unwrap_err()
            .to_string()
            .contains("still_blend"));
        assert!(TemporalConfig {
            cut_distance_m: f32::NAN,
            ..t
        }
        .validate()
        .is_err());
        assert!(never.validate().is_ok());
    }

    /// The shader's reach: accumulating everywhere, cosines no direction reaches; a reach, the
    /// cosine of its angle and, inside it, of its fade's start (clamped at the gaze). Out of
    /// range, an error naming the field.
    #[test]
    fn the_reach_encodes_as_cosines_and_is_checked() {
        let (end, fade) = TemporalConfig::default().reach_cosines();
        assert!(end < fade && fade < -1.0, "{end} {fade}");
        let at = |deg| TemporalConfig {
            within_deg: Some(deg),
            ..Default::default()
        };
        let (end, fade) = at(30.0).reach_cosines();
        assert!((end - 30f32.to_radians().cos()).abs() < 1e-6);
        assert!((fade - (30.0 - REACH_EDGE_DEG).to_radians().cos()).abs() < 1e-6);
        assert_eq!(at(2.0).reach_cosines().1, 1.0);
        for bad in [0.0, -5.0, 181.0, f32::NAN] {
            let e = at(bad).validate().unwrap_err();
            assert_eq!(e.field, "temporal_within_deg", "{bad}");
        }
        assert!(at(180.0).validate().is_ok());
    }

    /// Every clip reads back from the name it prints, and tells the shader whether to clip and
    /// whether to test depth. Mutation: `depth` parsed as `off` fails the round trip.
    #[test]
    fn clips_round_trip_and_encode() {
        for clip in [
            HistoryClip::Variance { sigmas: 2.0 },
            HistoryClip::Range,
            HistoryClip::Moved,
            HistoryClip::DepthOnly,
            HistoryClip::Off,
        ] {
            assert_eq!(clip.to_string().parse::<HistoryClip>().unwrap(), clip);
        }
        let encoded = |c: HistoryClip| (c.spread() >= 0.0, c.depth_test());
        assert_eq!(encoded(HistoryClip::DepthOnly), (false, 1.0));
        assert_eq!(encoded(HistoryClip::Off), (false, 0.0));
        assert_eq!(encoded(HistoryClip::Range), (true, 1.0));
        assert_eq!(encoded(HistoryClip::Moved), (true, 2.0));
        let err = "deep".parse::<HistoryClip>().unwrap_err().to_string();
        assert!(err.contains("deep") && err.contains("depth"), "{err}");
    }

    /// Both neighbourhoods read back from the names they print; a wrong name is refused,
    /// naming itself and the two it could be. Mutation: `cross` parsed as the 3×3 fails it.
    #[test]
    fn neighbourhoods_round_trip() {
        for n in [ClipNeighbourhood::Square, ClipNeighbourhood::Cross] {
            assert_eq!(n.to_string().parse::<ClipNeighbourhood>().unwrap(), n);
        }
        let err = "5x5".parse::<ClipNeighbourhood>().unwrap_err().to_string();
        assert!(err.contains("5x5") && err.contains("cross"), "{err}");
    }

    /// Both new samples read back from the names they print; a wrong name is refused, naming
    /// itself and the two it could be. Mutation: `nearest` parsed as weighted fails it.
    #[test]
    fn new_samples_round_trip() {
        for n in [NewSample::Nearest, NewSample::Weighted] {
            assert_eq!(n.to_string().parse::<NewSample>().unwrap(), n);
        }
        let err = "bilinear".parse::<NewSample>().unwrap_err().to_string();
        assert!(
            err.contains("bilinear") && err.contains("weighted"),
            "{err}"
        );
    }
}
