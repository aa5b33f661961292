//! What the viewer's keys change: the frame's configuration and shading, one key a setting.
//! Kept apart from the window so every key is tested without one.

use foveate::foveation::FoveationConfig;
use foveate::mffr::MffrConfig;
use foveate::plan::{FoveaLayout, RenderConfig, StereoMode};
use foveate::scene::Shading;

/// The keys, as `docs/commands/view.md` and the window's help line list them.
pub const KEYS: &[(char, &str)] = &[
    ('f', "foveation on/off"),
    ('[', "foveation ratio -0.05"),
    (']', "foveation ratio +0.05"),
    ('l', "fovea layout: auto, one-pass, two-pass"),
    ('m', "HMD stencil mask on/off"),
    (
        'p',
        "MFFR: off, far-first, near-first, alternate-eye, depth-shift",
    ),
    ('s', "stereo: multiview, two-pass, per-object, instanced"),
    ('h', "shading: flat/lit"),
    ('t', "tint overlay on/off"),
    ('q', "quit (also Esc)"),
];

const MFFR_MODES: [&str; 4] = ["far-first", "near-first", "alternate-eye", "depth-shift"];
const RATIO_RANGE: (f32, f32) = (0.2, 0.8);

/// The viewer's settings: a frame configuration and a shading.
#[derive(Clone, Debug, PartialEq)]
pub struct ViewSettings {
    pub config: RenderConfig,
    pub shading: Shading,
    /// Foveation as it was last on, kept while it is off so `f` brings it back unchanged.
    foveation: FoveationConfig,
}

/// What a key did.
#[derive(Clone, Debug, PartialEq)]
pub enum KeyAction {
    /// The frame must be planned again; says what changed.
    Changed(String),
    Quit,
    /// Not a key of the viewer's.
    Ignored,
}

impl ViewSettings {
    pub fn new(config: RenderConfig, shading: Shading) -> Self {
        let foveation = config.foveation.unwrap_or(FoveationConfig {
            ratio: 0.35,
            ..FoveationConfig::default()
        });
        ViewSettings {
            config,
            shading,
            foveation,
        }
    }

    /// Applies `key` (lower case).
    pub fn key(&mut self, key: char) -> KeyAction {
        let c = &mut self.config;
        let changed = |what: String| KeyAction::Changed(what);
        match key {
            'f' => {
                c.foveation = match c.foveation {
                    Some(f) => {
                        self.foveation = f;
                        None
                    }
                    None => Some(self.foveation),
                };
                changed(self.foveation_label())
            }
            '[' | ']' => {
                let step = if key == '[' { -0.05 } else { 0.05 };
                let f = c.foveation.get_or_insert(self.foveation);
                // Whole hundredths, so repeated steps land on the values a user types.
                f.ratio = ((f.ratio + step) * 100.0).round() / 100.0;
                f.ratio = f.ratio.clamp(RATIO_RANGE.0, RATIO_RANGE.1);
                self.foveation = *f;
                changed(self.foveation_label())
            }
            'l' => {
                c.fovea_layout = match c.fovea_layout {
                    FoveaLayout::Auto => FoveaLayout::OnePass,
                    FoveaLayout::OnePass => FoveaLayout::TwoPass,
                    FoveaLayout::TwoPass => FoveaLayout::Auto,
                };
                changed(format!("fovea layout {}", c.fovea_layout))
            }
            'm' => {
                c.hmd_mask = !c.hmd_mask;
                changed(format!("HMD mask {}", on_off(c.hmd_mask)))
            }
            'p' => {
                let now = c.mffr.map(|m| m.name());
                let next = match now.and_then(|n| MFFR_MODES.iter().position(|&m| m == n)) {
                    None => Some(MFFR_MODES[0]),
                    Some(i) => MFFR_MODES.get(i + 1).copied(),
                };
                let split = c.mffr.unwrap_or_default().split;
                c.mffr = next.map(|n| MffrConfig::named(n, split).expect("a known MFFR mode"));
                changed(format!("MFFR {}", next.unwrap_or("off")))
            }
            's' => {
                let i = StereoMode::ALL
                    .iter()
                    .position(|&m| m == c.stereo)
                    .unwrap_or(0);
                c.stereo = StereoMode::ALL[(i + 1) % StereoMode::ALL.len()];
                changed(format!("stereo {}", c.stereo))
            }
            'h' => {
                self.shading = match self.shading {
                    Shading::Flat => Shading::Lit,
                    Shading::Lit => Shading::Flat,
                };
                changed(format!("shading {}", self.shading))
            }
            't' => {
                let f = c.foveation.get_or_insert(self.foveation);
                f.debug_tint = !f.debug_tint;
                self.foveation = *f;
                changed(format!("tint {}", on_off(f.debug_tint)))
            }
            'q' => KeyAction::Quit,
            _ => KeyAction::Ignored,
        }
    }

    fn foveation_label(&self) -> String {
        match self.config.foveation {
            Some(f) => format!("foveated {:.2}", f.ratio),
            None => "stereo (foveation off)".into(),
        }
    }

    /// One line for the title bar.
    pub fn summary(&self) -> String {
        let c = &self.config;
        let mut parts = vec![self.foveation_label(), c.stereo.to_string()];
        if c.foveation.is_some() {
            parts.push(format!("layout {}", c.fovea_layout));
        }
        if c.hmd_mask {
            parts.push("HMD mask".into());
        }
        if let Some(m) = c.mffr {
            parts.push(format!("MFFR {}", m.name()));
        }
        parts.push(self.shading.to_string());
        parts.push(format!("MSAA {}", c.msaa));
        parts.join(", ")
    }
}

fn on_off(on: bool) -> &'static str {
    if on {
        "on"
    } else {
        "off"
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn settings() -> ViewSettings {
        ViewSettings::new(RenderConfig::default(), Shading::Flat)
    }

    #[test]
    fn foveation_toggles_and_keeps_its_ratio() {
        let mut s = settings();
        assert_eq!(s.key(']'), KeyAction::Changed("foveated 0.40".into()));
        assert_eq!(s.config.view_count(), 4);
        assert_eq!(
            s.key('f'),
            KeyAction::Changed("stereo (foveation off)".into())
        );
        assert_eq!((s.config.foveation, s.config.view_count()), (None, 2));
        s.key('f');
        assert_eq!(s.config.foveation.map(|f| f.ratio), Some(0.4));
        for _ in 0..20 {
            s.key('[');
        }
        assert_eq!(s.config.foveation.map(|f| f.ratio), Some(0.2), "clamped");
    }

    #[test]
    fn cycles_come_back_to_the_start() {
        let mut s = settings();
        let start = s.clone();
        for key in ['l', 's', 'h', 'm'] {
            let n = match key {
                'l' => 3,
                's' => StereoMode::ALL.len(),
                _ => 2,
            };
            for _ in 0..n {
                assert!(matches!(s.key(key), KeyAction::Changed(_)));
            }
            assert_eq!(s, start, "{key} cycles back");
        }
        let modes: Vec<String> = (0..5)
            .map(|_| match s.key('p') {
                KeyAction::Changed(what) => what,
                other => panic!("{other:?}"),
            })
            .collect();
        assert_eq!(
            modes,
            [
                "MFFR far-first",
                "MFFR near-first",
                "MFFR alternate-eye",
                "MFFR depth-shift",
                "MFFR off"
            ]
        );
        assert_eq!(s.config.mffr, None);
    }

    #[test]
    fn tint_turns_foveation_on_and_other_keys_are_ignored() {
        let mut s = settings();
        assert_eq!(s.key('t'), KeyAction::Changed("tint on".into()));
        assert!(s.config.foveation.is_some_and(|f| f.debug_tint));
        assert_eq!(s.key('q'), KeyAction::Quit);
        assert_eq!(s.key('z'), KeyAction::Ignored);
        assert!(s
            .summary()
            .starts_with("foveated 0.35, multiview, layout auto"));
    }
}
