//! The thesis' configuration matrix (Preißner 2020 §5.3): every permutation of its four
//! optimisations, and each multiview one again with foveation on — all runtime configuration.

use foveate::cull::Strategy;
use foveate::foveation::FoveationConfig;
use foveate::mffr::MffrConfig;
use foveate::plan::{CullConfig, RenderConfig, Resolution, StereoMode};
use serde::Serialize;

/// Which optimisations one configuration switches on.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
pub struct Toggles {
    /// HMD stencil mask (the thesis' `STENCILMASK_ON`).
    pub smask: bool,
    /// Superfrustum culling instead of per-eye frusta (`SUPERFRUSTUM_ON`).
    pub sfrust: bool,
    /// Multiview instead of one pass per eye (`MULTIVIEW_ON`).
    pub mview: bool,
    /// Monoscopic far-field rendering (`MFFR_ON`).
    pub mffr: bool,
    /// Foveated rendering: four views, composed per eye (needs multiview).
    pub foveate: bool,
}

impl Toggles {
    /// The thesis' 16 permutations, fewest switches first and in its naming order; then the
    /// multiview ones with foveation (foveation renders its four views with multiview, so
    /// two-pass rows have no foveated twin).
    pub fn matrix() -> Vec<Toggles> {
        let mut plain: Vec<Toggles> = (0u32..16)
            .map(|bits| Toggles {
                smask: bits & 1 != 0,
                sfrust: bits & 2 != 0,
                mview: bits & 4 != 0,
                mffr: bits & 8 != 0,
                foveate: false,
            })
            .collect();
        plain.sort_by_key(|t| (t.thesis_switches(), !t.smask, !t.sfrust, !t.mview, !t.mffr));
        let foveated: Vec<Toggles> = plain
            .iter()
            .filter(|t| t.mview)
            .map(|&t| Toggles { foveate: true, ..t })
            .collect();
        plain.into_iter().chain(foveated).collect()
    }

    /// How many of the thesis' four optimisations are on (foveation not counted).
    pub fn thesis_switches(self) -> usize {
        [self.smask, self.sfrust, self.mview, self.mffr]
            .iter()
            .filter(|&&b| b)
            .count()
    }

    /// The thesis' label: `baseline`, `SMASK & MVIEW`, …; foveated rows add `+ FOV`.
    pub fn name(self) -> String {
        let parts: Vec<&str> = [
            (self.smask, "SMASK"),
            (self.sfrust, "SFRUST"),
            (self.mview, "MVIEW"),
            (self.mffr, "MFFR"),
            (self.foveate, "FOV"),
        ]
        .iter()
        .filter(|(on, _)| *on)
        .map(|&(_, n)| n)
        .collect();
        if parts.is_empty() {
            "baseline".into()
        } else {
            parts.join(" & ")
        }
    }

    pub fn is_baseline(self) -> bool {
        self == Toggles::default()
    }
}

/// What every configuration shares.
#[derive(Clone, Debug)]
pub struct Settings {
    pub hmd: String,
    pub resolution: Resolution,
    pub msaa: u32,
    pub draw_distance: f32,
    pub foveation: FoveationConfig,
    pub mffr: MffrConfig,
}

impl Settings {
    /// The frame configuration of `t`: distance and frustum culling always on (as in every
    /// thesis run), per-eye frusta unless the superfrustum is on.
    pub fn config(&self, t: Toggles) -> RenderConfig {
        RenderConfig {
            hmd: self.hmd.clone(),
            resolution: Some(self.resolution),
            stereo: if t.mview {
                StereoMode::Multiview
            } else {
                StereoMode::TwoPass
            },
            msaa: self.msaa,
            // Far enough for everything within the draw distance.
            far: self.draw_distance * 2.0,
            count_fragments: false,
            timestamps: true,
            foveation: t.foveate.then_some(self.foveation),
            hmd_mask: t.smask,
            mffr: t.mffr.then_some(self.mffr),
            culling: Some(CullConfig {
                strategy: if t.sfrust {
                    Strategy::Superfrustum
                } else {
                    Strategy::PerEye
                },
                draw_distance: self.draw_distance,
            }),
            ..RenderConfig::default()
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_matrix_is_the_thesis_sixteen_and_eight_foveated() {
        let m = Toggles::matrix();
        assert_eq!(m.len(), 24);
        assert!(m[0].is_baseline());
        let names: Vec<String> = m.iter().map(|t| t.name()).collect();
        assert_eq!(&names[1..5], ["SMASK", "SFRUST", "MVIEW", "MFFR"]);
        assert_eq!(names[15], "SMASK & SFRUST & MVIEW & MFFR");
        assert!(m[16..].iter().all(|t| t.foveate && t.mview));
        let unique: std::collections::HashSet<_> = names.iter().collect();
        assert_eq!(unique.len(), 24);
    }
}
