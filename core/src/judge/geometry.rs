//! Where the judge works: the pyramid's levels (each the image halved, padded past its edges by
//! its filters' reach), and the rectangles of pixels and texels each ppd level needs.

use crate::metrics::acuity::LEVELS;

/// The smallest side a pyramid level may have.
const MIN_LEVEL_SIDE: u32 = 16;

/// One pyramid level: its size, how far it extends past the judged image on each side, and
/// where its reference image starts (its test image follows).
#[derive(Clone, Copy, Debug)]
pub(super) struct PyramidLevel {
    pub(super) width: u32,
    pub(super) height: u32,
    pub(super) pad: u32,
    pub(super) offset: u32,
}

/// A rectangle of pixels or texels: `min` inclusive, `max` exclusive.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Region {
    pub(super) min: [u32; 2],
    pub(super) max: [u32; 2],
}

impl Region {
    pub(super) fn point(x: u32, y: u32) -> Region {
        Region {
            min: [x, y],
            max: [x + 1, y + 1],
        }
    }

    pub(super) fn union(self, other: Region) -> Region {
        Region {
            min: [self.min[0].min(other.min[0]), self.min[1].min(other.min[1])],
            max: [self.max[0].max(other.max[0]), self.max[1].max(other.max[1])],
        }
    }

    pub(super) fn extent(&self) -> (u32, u32) {
        (self.max[0] - self.min[0], self.max[1] - self.min[1])
    }
}

/// Per ppd level, the region of the judged pixels that take a share of it (level 0: every
/// judged pixel, for the plain map); `None` for a level no pixel needs.
pub(super) type LevelRegions = [Option<Region>; LEVELS.len()];

pub(super) fn add_to(regions: &mut LevelRegions, level: usize, x: u32, y: u32) {
    let point = Region::point(x, y);
    regions[level] = Some(regions[level].map_or(point, |r| r.union(point)));
}

pub(super) fn merge(mut a: LevelRegions, b: LevelRegions) -> LevelRegions {
    for (r, other) in a.iter_mut().zip(b) {
        *r = match (*r, other) {
            (Some(x), Some(y)) => Some(x.union(y)),
            (x, y) => x.or(y),
        };
    }
    a
}

/// The texels of pyramid level `at` (judged pixels per texel `scale`) that the pixels of
/// `region` sample (Catmull-Rom: the 4×4 texels around each).
pub(super) fn level_region(region: Region, at: &PyramidLevel, scale: f32) -> Region {
    let texel = |x: u32| (x as f32 + 0.5) / scale + at.pad as f32 - 0.5;
    let low = |x: u32| texel(x).floor().max(0.0) as u32;
    Region {
        min: [
            low(region.min[0]).saturating_sub(1),
            low(region.min[1]).saturating_sub(1),
        ],
        max: [
            (low(region.max[0] - 1) + 3).min(at.width),
            (low(region.max[1] - 1) + 3).min(at.height),
        ],
    }
}

pub(super) fn origin(region: &Region) -> [i32; 2] {
    [region.min[0] as i32, region.min[1] as i32]
}

/// How many pyramid levels `width` × `height` allows, the judged resolution included: each
/// halves the image (rounding up) while both sides keep at least [`MIN_LEVEL_SIDE`], one per
/// ppd level at most.
pub(super) fn pyramid_depth(width: u32, height: u32) -> u32 {
    let (mut w, mut h, mut depth) = (width, height, 1);
    while depth < LEVELS.len() as u32
        && w.div_ceil(2) >= MIN_LEVEL_SIDE
        && h.div_ceil(2) >= MIN_LEVEL_SIDE
    {
        (w, h) = (w.div_ceil(2), h.div_ceil(2));
        depth += 1;
    }
    depth
}

/// The pyramid for `pads` (texels past the image on each side, per level; level 0 has none):
/// level p is the image halved p times (rounding up), plus its padding; each level's two
/// images packed after the last's.
pub(super) fn pyramid_levels(width: u32, height: u32, pads: &[u32]) -> Vec<PyramidLevel> {
    let (mut w, mut h, mut offset) = (width, height, 0);
    let mut levels = Vec::with_capacity(pads.len());
    for (p, &pad) in pads.iter().enumerate() {
        if p > 0 {
            (w, h) = (w.div_ceil(2), h.div_ceil(2));
        }
        let level = PyramidLevel {
            width: w + 2 * pad,
            height: h + 2 * pad,
            pad,
            offset,
        };
        offset += 2 * level.width * level.height;
        levels.push(level);
    }
    levels
}
