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
    /// Its name in full, for the printout.
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
    /// The panel's highest refresh rate (Hz).
    pub refresh_hz: f32,
    /// The built-in eye tracker, for headsets that have one (eye-tracked foveation needs it).
    pub eye_tracker: Option<EyeTracker>,
    /// Where the figures come from, and which are estimated, in a line `foveate plan` prints.
    pub source: &'static str,
}

/// A headset's eye tracker, as far as its maker or a measurement publishes it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EyeTracker {
    /// Gaze samples per second, where published.
    pub rate_hz: Option<f32>,
    /// End-to-end latency from the eye's movement to the gaze reaching the application (ms),
    /// where measured.
    pub latency_ms: Option<f32>,
}

/// The lens model every profile uses. Valve, HTC and Meta publish no distortion coefficients
/// (their runtimes read per-unit factory calibration), so each profile takes the published
/// coefficients of a lens of the same kind, a single-element pincushion magnifier: Google
/// Cardboard's 2015 viewer (Cardboard SDK viewer profile "Cardboard I/O 2015": k1 = 0.34,
/// k2 = 0.55, tangent units). The display's extent is then solved per headset so that its edges
/// show exactly the rendered field (`RadialDistortion::display_fov`). Distorted output is
/// therefore representative of a VR lens, not these headsets' exact images.
pub const CARDBOARD_2015_LENS: RadialDistortion = RadialDistortion { k1: 0.34, k2: 0.55 };

/// The interpupillary distance used when a profile has none: 64 mm.
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
        refresh_hz: 144.0,
        eye_tracker: None,
        source: "Valve spec (panel, 144 Hz); tangents ≈ hmdgdb users, ±2°; lens: Cardboard 2015 stand-in",
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
        refresh_hz: 90.0,
        eye_tracker: None,
        source: "HTC spec (panel, 90 Hz); tangents and hidden area: hmdq (hmdgdb); lens: Cardboard 2015 stand-in",
    },
    // Oculus Rift CV1: 1080×1200 OLED per eye (Oculus specification). Tangents: Oculus runtime
    // default FOV of the left eye as recorded by hmdq (hmdgdb, "Oculus Rift CV1 (90Hz)"):
    // left 0.964926, right 0.715264, up 0.889498, down 1.110925 — the asymmetric eye Hale's
    // thesis (Hale 2018, §4) struggled to fit with a circular cone.
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
        refresh_hz: 90.0,
        eye_tracker: None,
        source: "Oculus spec (panel, 90 Hz); tangents and hidden area: hmdq (hmdgdb); lens: Cardboard 2015 stand-in",
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
        refresh_hz: 120.0,
        eye_tracker: None,
        source: "Meta spec (panel, 120 Hz); tangents and hidden area: hmdq (hmdgdb); lens: Cardboard 2015 stand-in",
    },
    // --- Eye-tracked headsets and the volume headset. No per-eye tangents are
    // recorded for these in the sources we have (hmdgdb has none), so each field is estimated
    // from the maker's published field of view: the published horizontal figure is taken as the
    // binocular field, each eye's outer half-angle half of it and its inner one 7° less (the
    // asymmetry hmdq recorded for Quest 2: 52° out, 45° in); the vertical field symmetric, or
    // where none is published, from the panel's aspect at square pixels. Every one of these
    // headsets uses a pancake or aspheric lens whose coefficients are unpublished; the Cardboard
    // stand-in distorts more than they do, so lens-output error figures are pessimistic.
    // Meta Quest Pro: 1800×1920 LCD per eye, 90 Hz, 106° H × 96° V (Meta's specification);
    // eye tracking built in; rate unpublished; ≈ 50 ms end-to-end latency as measured reports
    // put it (estimated).
    HmdProfile {
        name: "quest-pro",
        display_name: "Meta Quest Pro",
        panel_per_eye: (1800, 1920),
        left_fov: FovTangents {
            left: 1.327045,
            right: 1.035530,
            up: 1.110613,
            down: 1.110613,
        },
        cant_rad: 0.0,
        hidden_area_fraction: None,
        distortion: CARDBOARD_2015_LENS,
        refresh_hz: 90.0,
        eye_tracker: Some(EyeTracker {
            rate_hz: None,
            latency_ms: Some(50.0),
        }),
        source: "Meta spec (panel, 90 Hz, 106°x96°); tangents estimated from the spec's field; tracker latency ≈ 50 ms measured (estimated)",
    },
    // Meta Quest 3: 2064×2208 LCD per eye, up to 120 Hz, 110° H × 96° V (Meta's specification);
    // no eye tracking — the volume headset, for fixed foveation only.
    HmdProfile {
        name: "quest3",
        display_name: "Meta Quest 3",
        panel_per_eye: (2064, 2208),
        left_fov: FovTangents {
            left: 1.428148,
            right: 1.110613,
            up: 1.110613,
            down: 1.110613,
        },
        cant_rad: 0.0,
        hidden_area_fraction: None,
        distortion: CARDBOARD_2015_LENS,
        refresh_hz: 120.0,
        eye_tracker: None,
        source: "Meta spec (panel, 120 Hz, 110°x96°); tangents estimated from the spec's field",
    },
    // Sony PlayStation VR2: 2000×2040 OLED per eye, 90/120 Hz, "approx. 110°" field (Sony's
    // specification); eye tracking by one IR camera per eye (Sony); rate unpublished. The
    // vertical field is estimated from the panel's aspect.
    HmdProfile {
        name: "psvr2",
        display_name: "Sony PlayStation VR2",
        panel_per_eye: (2000, 2040),
        left_fov: FovTangents {
            left: 1.428148,
            right: 1.110613,
            up: 1.294768,
            down: 1.294768,
        },
        cant_rad: 0.0,
        hidden_area_fraction: None,
        distortion: CARDBOARD_2015_LENS,
        refresh_hz: 120.0,
        eye_tracker: Some(EyeTracker {
            rate_hz: None,
            latency_ms: None,
        }),
        source: "Sony spec (panel, 120 Hz, approx. 110°); tangents estimated (vertical from the panel's aspect)",
    },
    // Apple Vision Pro: "23 million pixels" over two micro-OLED panels, 90/96/100 Hz (Apple's
    // specification); per eye ≈ 3660×3200 as teardowns report it (estimated); Apple publishes
    // no field of view: ≈ 100° horizontal as reviewers measured it (estimated), vertical from the
    // panel's aspect. Eye tracking built in (Apple); rate unpublished.
    HmdProfile {
        name: "vision-pro",
        display_name: "Apple Vision Pro",
        panel_per_eye: (3660, 3200),
        left_fov: FovTangents {
            left: 1.191754,
            right: 0.932515,
            up: 0.928642,
            down: 0.928642,
        },
        cant_rad: 0.0,
        hidden_area_fraction: None,
        distortion: CARDBOARD_2015_LENS,
        refresh_hz: 100.0,
        eye_tracker: Some(EyeTracker {
            rate_hz: None,
            latency_ms: None,
        }),
        source: "Apple spec (23 Mpx, 100 Hz); per-eye panel and ≈100° field estimated (teardowns, reviews)",
    },
    // Samsung Galaxy XR: 3552×3840 micro-OLED per eye ("27 million pixels"), up to 90 Hz,
    // 109° H × 100° V (Samsung's specification); eye tracking built in (Samsung); rate
    // unpublished.
    HmdProfile {
        name: "galaxy-xr",
        display_name: "Samsung Galaxy XR",
        panel_per_eye: (3552, 3840),
        left_fov: FovTangents {
            left: 1.401948,
            right: 1.091309,
            up: 1.191754,
            down: 1.191754,
        },
        cant_rad: 0.0,
        hidden_area_fraction: None,
        distortion: CARDBOARD_2015_LENS,
        refresh_hz: 90.0,
        eye_tracker: Some(EyeTracker {
            rate_hz: None,
            latency_ms: None,
        }),
        source: "Samsung spec (panel, 90 Hz, 109°x100°); tangents estimated from the spec's field",
    },
    // Varjo XR-4: 3840×3744 mini-LED LCD per eye, 90 Hz, 120° H × 105° V, eye tracking at
    // 200 Hz (Varjo's specification).
    HmdProfile {
        name: "varjo-xr4",
        display_name: "Varjo XR-4",
        panel_per_eye: (3840, 3744),
        left_fov: FovTangents {
            left: 1.732051,
            right: 1.327045,
            up: 1.303225,
            down: 1.303225,
        },
        cant_rad: 0.0,
        hidden_area_fraction: None,
        distortion: CARDBOARD_2015_LENS,
        refresh_hz: 90.0,
        eye_tracker: Some(EyeTracker {
            rate_hz: Some(200.0),
            latency_ms: None,
        }),
        source: "Varjo spec (panel, 90 Hz, 120°x105°, tracker 200 Hz); tangents estimated from the spec's field",
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
    /// (the ellipse inscribed in the image, hiding 1 − π/4 ≈ 21.5 %; Preißner 2020 §4.2's "fast
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

    /// Each profile's figures against its source's, as published (degrees, pixels, Hz):
    /// horizontal field binocular (each eye's outer half-angle twice) where the source gives
    /// one, per eye for hmdq's recordings. Mutation: a tangent from the wrong headset, a panel's
    /// width and height swapped, or a tracker on Quest 3 fails it.
    #[test]
    // Tangents quoted digit for digit from their source.
    #[allow(clippy::excessive_precision)]
    fn profiles_match_their_sources() {
        struct Published {
            name: &'static str,
            panel: (u32, u32),
            /// hmdq's recorded raw tangents (left, right, up, down), or the maker's binocular
            /// horizontal field in degrees.
            field: Field,
            vertical_deg: Option<f32>,
            refresh_hz: f32,
            eye_tracked: bool,
            tracker_hz: Option<f32>,
        }
        enum Field {
            Recorded([f32; 4]),
            Binocular(f32),
        }
        use Field::*;
        #[rustfmt::skip]
        let table = [
            Published { name: "vive", panel: (1080, 1200), field: Recorded([1.397283, 1.250510, 1.464221, 1.477517]), vertical_deg: None, refresh_hz: 90.0, eye_tracked: false, tracker_hz: None },
            Published { name: "rift-cv1", panel: (1080, 1200), field: Recorded([0.964926, 0.715264, 0.889498, 1.110925]), vertical_deg: None, refresh_hz: 90.0, eye_tracked: false, tracker_hz: None },
            Published { name: "quest2", panel: (1832, 1920), field: Recorded([1.279942, 1.0, 1.110613, 1.191754]), vertical_deg: None, refresh_hz: 120.0, eye_tracked: false, tracker_hz: None },
            Published { name: "quest-pro", panel: (1800, 1920), field: Binocular(106.0), vertical_deg: Some(96.0), refresh_hz: 90.0, eye_tracked: true, tracker_hz: None },
            Published { name: "quest3", panel: (2064, 2208), field: Binocular(110.0), vertical_deg: Some(96.0), refresh_hz: 120.0, eye_tracked: false, tracker_hz: None },
            Published { name: "psvr2", panel: (2000, 2040), field: Binocular(110.0), vertical_deg: None, refresh_hz: 120.0, eye_tracked: true, tracker_hz: None },
            Published { name: "vision-pro", panel: (3660, 3200), field: Binocular(100.0), vertical_deg: None, refresh_hz: 100.0, eye_tracked: true, tracker_hz: None },
            Published { name: "galaxy-xr", panel: (3552, 3840), field: Binocular(109.0), vertical_deg: Some(100.0), refresh_hz: 90.0, eye_tracked: true, tracker_hz: None },
            Published { name: "varjo-xr4", panel: (3840, 3744), field: Binocular(120.0), vertical_deg: Some(105.0), refresh_hz: 90.0, eye_tracked: true, tracker_hz: Some(200.0) },
        ];
        let deg = |t: f32| t.atan().to_degrees();
        for row in &table {
            let p = HmdProfile::by_name(row.name).unwrap();
            let f = p.left_fov;
            assert_eq!(p.panel_per_eye, row.panel, "{}", row.name);
            assert_eq!(p.refresh_hz, row.refresh_hz, "{}", row.name);
            assert_eq!(p.eye_tracker.is_some(), row.eye_tracked, "{}", row.name);
            assert_eq!(
                p.eye_tracker.and_then(|t| t.rate_hz),
                row.tracker_hz,
                "{}",
                row.name
            );
            let binocular = 2.0 * deg(f.left);
            match row.field {
                Recorded(t) => assert_eq!(f.as_array(), t, "{}", row.name),
                Binocular(published) => {
                    assert!(
                        (binocular - published).abs() < 0.1,
                        "{}: {binocular}",
                        row.name
                    );
                    assert!(
                        (deg(f.left) - deg(f.right) - 7.0).abs() < 0.01,
                        "{}",
                        row.name
                    );
                }
            }
            let vertical = deg(f.up) + deg(f.down);
            match row.vertical_deg {
                Some(published) => {
                    assert!(
                        (vertical - published).abs() < 0.1,
                        "{}: {vertical}",
                        row.name
                    )
                }
                None if matches!(row.field, Recorded(_)) => {}
                // Estimated from the panel's aspect: equal tangent pitch across and down.
                None => {
                    let pitch = |t: f32, px: u32| t / px as f32;
                    let (across, down) = (
                        pitch(f.left + f.right, row.panel.0),
                        pitch(f.up + f.down, row.panel.1),
                    );
                    assert!((across / down - 1.0).abs() < 1e-4, "{}", row.name);
                }
            }
        }
        assert!(
            table.len() + 1 == HMD_PROFILES.len(),
            "every profile but the index (no recording) has its row"
        );
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
