use super::{EyeParams, FovTangents, LensRegion, RadialDistortion};

/// A headset model: its per-eye panel resolution and its eyes' field of view.
///
/// FOV tangents are the left eye's; the right eye is its mirror image (true to a few 0.1 % for
/// each of these headsets). IPD defaults to 64 mm, near the adult mean, since a headset's
/// reported IPD is the wearer's setting rather than a property of the device.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HmdProfile {
    /// Short name used on the command line (`--hmd index`).
    pub name: &'static str,
    pub display_name: &'static str,
    /// Physical panel pixels per eye (width, height).
    pub panel_per_eye: (u32, u32),
    /// Left eye FOV tangents (the right eye mirrors them).
    pub left_fov: FovTangents,
    /// Outward cant of each eye's view in radians.
    pub cant_rad: f32,
    /// Fraction of each eye's image hidden by the lens (the hidden-area mesh's area), where
    /// published; `None` treats the whole image as visible.
    pub hidden_area_fraction: Option<f32>,
    /// The lens's radial distortion, which the output stage counters.
    pub distortion: RadialDistortion,
}

/// The lens model every profile uses. Valve, HTC and Meta publish no distortion coefficients
/// (their runtimes read per-unit factory calibration), so each profile takes the published
/// coefficients of a lens of the same kind, a single-element pincushion magnifier: Google
/// Cardboard's 2015 viewer (Cardboard SDK viewer profile "Cardboard I/O 2015": k1 = 0.34,
/// k2 = 0.55, tangent units). The display's extent is then solved per headset so that its edges
/// show exactly the rendered field (`RadialDistortion::display_fov`). Distorted output is
/// therefore representative of a VR lens, not these headsets' exact images.
pub const CARDBOARD_2015_LENS: RadialDistortion = RadialDistortion { k1: 0.34, k2: 0.55 };

pub const DEFAULT_IPD_M: f32 = 0.064;

/// The profiles foveate knows, each citing where its numbers come from.
// Tangents are quoted digit for digit from their source, more digits than f32 keeps.
#[allow(clippy::excessive_precision)]
pub const HMD_PROFILES: &[HmdProfile] = &[
    // Valve Index: 1440×1600 LCD per eye (Valve's published specification). Valve does not
    // publish per-eye tangents; these are approximate values of the OpenVR raw projection as
    // reported for the Index by users of hmdq (HMD Geometry Database, risa2000.github.io/hmdgdb);
    // treat them as ±2°.
    HmdProfile {
        name: "index",
        display_name: "Valve Index",
        panel_per_eye: (1440, 1600),
        left_fov: FovTangents {
            left: 1.396,
            right: 1.240,
            up: 1.466,
            down: 1.471,
        },
        cant_rad: 0.0,
        // No recorded hidden-area mesh area in the sources we have.
        hidden_area_fraction: None,
        distortion: CARDBOARD_2015_LENS,
    },
    // HTC Vive: 1080×1200 OLED per eye (HTC specification). Tangents: OpenVR raw LRBT of the
    // left eye as recorded by hmdq (hmdgdb, "HTC Vive (90Hz)"): −1.397283, 1.250510,
    // −1.477517, 1.464221.
    HmdProfile {
        name: "vive",
        display_name: "HTC Vive",
        panel_per_eye: (1080, 1200),
        left_fov: FovTangents {
            left: 1.397283,
            right: 1.250510,
            up: 1.464221,
            down: 1.477517,
        },
        cant_rad: 0.0,
        // hmdq: "Left eye HAM mesh ... mesh area: 19.10 %".
        hidden_area_fraction: Some(0.1910),
        distortion: CARDBOARD_2015_LENS,
    },
    // Oculus Rift CV1: 1080×1200 OLED per eye (Oculus specification). Tangents: Oculus runtime
    // default FOV of the left eye as recorded by hmdq (hmdgdb, "Oculus Rift CV1 (90Hz)"):
    // left 0.964926, right 0.715264, up 0.889498, down 1.110925 — the asymmetric eye Hale's
    // thesis (seed 002, §4) struggled to fit with a circular cone.
    HmdProfile {
        name: "rift-cv1",
        display_name: "Oculus Rift CV1",
        panel_per_eye: (1080, 1200),
        left_fov: FovTangents {
            left: 0.964926,
            right: 0.715264,
            up: 0.889498,
            down: 1.110925,
        },
        cant_rad: 0.0,
        // hmdq: "mesh area: 14.07 %".
        hidden_area_fraction: Some(0.1407),
        distortion: CARDBOARD_2015_LENS,
    },
    // Meta Quest 2: 1832×1920 LCD per eye (Meta specification). Tangents: Oculus runtime default
    // FOV of the left eye as recorded by hmdq (hmdgdb, "Oculus Quest 2 (72Hz)"): left 1.279942
    // (52°), right 1.0 (45°), up 1.110613 (48°), down 1.191754 (50°).
    HmdProfile {
        name: "quest2",
        display_name: "Meta Quest 2",
        panel_per_eye: (1832, 1920),
        left_fov: FovTangents {
            left: 1.279942,
            right: 1.0,
            up: 1.110613,
            down: 1.191754,
        },
        cant_rad: 0.0,
        // hmdq: "mesh area: 9.13 %".
        hidden_area_fraction: Some(0.0913),
        distortion: CARDBOARD_2015_LENS,
    },
];

impl HmdProfile {
    /// Looks a profile up by its short name (case-insensitive).
    pub fn by_name(name: &str) -> Option<&'static HmdProfile> {
        HMD_PROFILES
            .iter()
            .find(|p| p.name.eq_ignore_ascii_case(name))
    }

    /// The names `by_name` accepts, for error messages and `--help`.
    pub fn names() -> Vec<&'static str> {
        HMD_PROFILES.iter().map(|p| p.name).collect()
    }

    /// The lens-visible region of an eye with field of view `fov`: an ellipse hiding the
    /// published hidden-area fraction or, for a profile without one, the circular fallback
    /// (the ellipse inscribed in the image, hiding 1 − π/4 ≈ 21.5 %; seed 000 §4.2's "fast
    /// circular approximation mask").
    pub fn lens_region(&self, fov: FovTangents) -> LensRegion {
        match self.hidden_area_fraction {
            Some(hidden) => LensRegion::with_hidden_fraction(fov, hidden),
            None => LensRegion { fov, scale: 1.0 },
        }
    }

    /// The profile's eye pair with the given IPD.
    pub fn eyes(&self, ipd_m: f32) -> EyeParams {
        EyeParams {
            left_fov: self.left_fov,
            right_fov: self.left_fov.mirrored(),
            ipd_m,
            cant_rad: self.cant_rad,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_profile_is_found_by_name_and_sane() {
        for p in HMD_PROFILES {
            assert_eq!(HmdProfile::by_name(p.name), Some(p));
            let t = p.left_fov.as_array();
            assert!(
                t.iter().all(|v| v.is_finite() && *v > 0.3 && *v < 3.0),
                "{}",
                p.name
            );
        }
        assert!(HmdProfile::by_name("pimax").is_none());
    }

    #[test]
    fn rift_cv1_matches_hales_angles() {
        // Hale: "around 42° to the left, 36° to the right, 47° up and 41° down" — for the
        // outer-eye view; the runtime's left eye has the larger angle down and to the left.
        let f = HmdProfile::by_name("rift-cv1").unwrap().left_fov;
        let deg = |t: f32| t.atan().to_degrees();
        assert!((deg(f.left) - 44.0).abs() < 1.0 && (deg(f.right) - 35.6).abs() < 1.0);
    }
}
