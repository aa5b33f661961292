use std::fmt;
use std::str::FromStr;

use super::ConfigError;

/// Per-eye render resolution in pixels.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Resolution {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
}

impl Resolution {
    /// `n` × `n` pixels.
    pub fn square(n: u32) -> Self {
        Self {
            width: n,
            height: n,
        }
    }

    /// Each side times `factor`, rounded, at least a pixel: a view at a density of the screen's.
    pub fn scaled(self, factor: f32) -> Self {
        let side = |px: u32| ((px as f32 * factor).round() as u32).max(1);
        Self {
            width: side(self.width),
            height: side(self.height),
        }
    }

    /// Width times height.
    pub fn pixels(self) -> u64 {
        self.width as u64 * self.height as u64
    }
}

impl fmt::Display for Resolution {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}x{}", self.width, self.height)
    }
}

impl FromStr for Resolution {
    type Err = ConfigError;
    /// `1024` (square) or `1440x1600`.
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        let bad = || ConfigError::new("resolution", s, "a pixel count `N` or `WxH`");
        let parse = |t: &str| t.trim().parse::<u32>().map_err(|_| bad());
        match s.split_once(['x', 'X']) {
            Some((w, h)) => Ok(Resolution {
                width: parse(w)?,
                height: parse(h)?,
            }),
            None => parse(s).map(Resolution::square),
        }
    }
}
