use std::fmt;
use std::str::FromStr;

use crate::vocab::ConfigError;

/// Where the near field ends and the far field begins.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SplitDistance {
    /// The distance at which the two eyes' images of a point differ by this many pixels:
    /// z = IPD · focal_px / threshold. Beyond it, a mono image is off by at most half of it
    /// in each eye.
    DisparityPx(f32),
    /// An explicit distance in metres along the view axis.
    Metres(f32),
}

impl fmt::Display for SplitDistance {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            SplitDistance::DisparityPx(px) => write!(f, "{px}px"),
            SplitDistance::Metres(m) => write!(f, "{m}m"),
        }
    }
}

impl FromStr for SplitDistance {
    type Err = ConfigError;
    /// `1px` (a disparity threshold) or `40m` (metres).
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        let bad = || {
            ConfigError::new(
                "mffr split",
                s,
                "a disparity like `1px` or metres like `40m`",
            )
        };
        let t = s.trim();
        if let Some(px) = t.strip_suffix("px") {
            px.trim()
                .parse()
                .map(SplitDistance::DisparityPx)
                .map_err(|_| bad())
        } else if let Some(m) = t.strip_suffix('m') {
            m.trim()
                .parse()
                .map(SplitDistance::Metres)
                .map_err(|_| bad())
        } else {
            Err(bad())
        }
    }
}

/// Which field reaches each eye's pixels first (Preißner 2020 §4.3.2–4.3.3).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum MffrOrder {
    /// The far image is composited into every eye pixel, then the near field drawn over it.
    FarFirst,
    /// The near field is drawn first and marks its pixels in stencil; the far image fills only
    /// the pixels it left uncovered.
    NearFirst,
}

/// How the far image reaches each eye.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum MffrVariant {
    /// Rendered from the head centre, reprojected by rotation only: each eye is off by half the
    /// disparity of what it sees.
    Centre,
    /// Rendered from the left eye on even frames and the right eye on odd ones (Preißner 2020
    /// §4.3.7): one eye exact, the other off by the full disparity, alternating.
    AlternateEye,
    /// Rendered from the head centre and shifted per pixel by its own depth (Preißner 2020 §4.3.6).
    DepthShift,
}

/// Monoscopic far-field rendering, as the user asks for it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MffrConfig {
    /// Where the far field begins.
    pub split: SplitDistance,
    /// Which field is drawn first.
    pub order: MffrOrder,
    /// Where the far view is rendered from.
    pub variant: MffrVariant,
    /// The far pass's MSAA samples (`None`: the frame's). Far edges move less than a pixel
    /// between the eyes but alias like near ones: fewer samples are a price in accuracy.
    pub far_msaa: Option<u32>,
    /// The far image's pixel density, as a fraction of the eyes' ([`FAR_DENSITY_RANGE`];
    /// [`MffrConfig::default`]: 0.8). 1 is exact up to the disparity bound; below it the far
    /// field is resampled, a price in accuracy for fewer far fragments.
    pub far_density: f32,
}

/// The far image's pixel densities a plan accepts, as fractions of the eyes'.
pub const FAR_DENSITY_RANGE: std::ops::RangeInclusive<f32> = 0.25..=1.0;

/// Near-first from the head centre at a 1 px split, the far pass at the frame's samples and 0.8
/// of the eyes' density: on the city at 1024² per eye (4×, lavapipe), the cheapest far setting
/// measured as accurate as aliased stereo (eFLIP p99 0.0608 on Mesa 22.3 and 25.0 alike), with
/// 35 % fewer far fragments than full density and faster in each of four paired runs on the two
/// drivers. A 1× far pass is cheaper on lavapipe (which pays per sample; a tile GPU resolves 4×
/// nearly free) but 14 % worse in eFLIP p99; 0.75 is 2 % worse, full density 1 % better.
impl Default for MffrConfig {
    fn default() -> Self {
        Self {
            split: SplitDistance::DisparityPx(1.0),
            order: MffrOrder::NearFirst,
            variant: MffrVariant::Centre,
            far_msaa: None,
            far_density: 0.8,
        }
    }
}

impl MffrConfig {
    /// The variants `foveate mffr` compares, by name.
    pub const NAMED: [(&'static str, MffrOrder, MffrVariant); 4] = [
        ("far-first", MffrOrder::FarFirst, MffrVariant::Centre),
        ("near-first", MffrOrder::NearFirst, MffrVariant::Centre),
        (
            "alternate-eye",
            MffrOrder::NearFirst,
            MffrVariant::AlternateEye,
        ),
        ("depth-shift", MffrOrder::NearFirst, MffrVariant::DepthShift),
    ];

    /// A named variant (see [`MffrConfig::NAMED`]) at `split`.
    pub fn named(name: &str, split: SplitDistance) -> Result<Self, ConfigError> {
        let names: Vec<&str> = Self::NAMED.iter().map(|n| n.0).collect();
        Self::NAMED
            .iter()
            .find(|n| n.0 == name)
            .map(|&(_, order, variant)| MffrConfig {
                split,
                order,
                variant,
                ..MffrConfig::default()
            })
            .ok_or_else(|| ConfigError::new("mffr", name, format!("one of {}", names.join(", "))))
    }

    /// Its name on the command line (`--mffr`).
    pub fn name(&self) -> &'static str {
        match (self.order, self.variant) {
            (MffrOrder::FarFirst, MffrVariant::Centre) => "far-first",
            (MffrOrder::NearFirst, MffrVariant::Centre) => "near-first",
            (_, MffrVariant::AlternateEye) => "alternate-eye",
            (_, MffrVariant::DepthShift) => "depth-shift",
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn split_parses_pixels_and_metres_and_rejects_the_rest() {
        assert_eq!("1px".parse(), Ok(SplitDistance::DisparityPx(1.0)));
        assert_eq!("40m".parse(), Ok(SplitDistance::Metres(40.0)));
        let e = "40".parse::<SplitDistance>().unwrap_err().to_string();
        assert!(e.contains("mffr split") && e.contains("40"), "{e}");
    }

    #[test]
    fn every_named_variant_round_trips() {
        for (name, _, _) in MffrConfig::NAMED {
            let c = MffrConfig::named(name, SplitDistance::Metres(30.0)).unwrap();
            assert_eq!(c.name(), name);
        }
        assert!(MffrConfig::named("both", SplitDistance::Metres(30.0)).is_err());
    }
}
