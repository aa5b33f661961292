//! Procedural textures for the built-in lit materials, made at load (no external assets): per
//! pattern a base colour (sRGB), a tangent-space normal map (from a height field) and an
//! occlusion-roughness-metallic map, each tileable and with its full mip chain.

use glam::{Vec2, Vec3};

use super::Pattern;

/// Side of every procedural texture, in texels (a power of two: 9 mip levels).
pub const TEXTURE_SIZE: u32 = 256;

/// An RGBA8 texture with its full mip chain, level 0 first, each level row-major.
#[derive(Clone, Debug, PartialEq)]
pub struct Texture {
    /// Level 0's width and height (a power of two).
    pub size: u32,
    /// Each level's RGBA8 texels, level 0 first.
    pub levels: Vec<Vec<u8>>,
}

/// A material's three textures.
#[derive(Clone, Debug, PartialEq)]
pub struct MaterialTextures {
    /// sRGB base colour.
    pub base: Texture,
    /// Tangent-space normal, `xyz · 0.5 + 0.5` (x along u, y along v as texture rows grow);
    /// alpha: the length of the mean of the level-0 normals the texel covers (1 at level 0,
    /// shorter where the normals it averages diverge), which specular anti-aliasing widens the
    /// highlight by (Toksvig 2005, "Mipmapping Normal Maps").
    pub normal: Texture,
    /// r occlusion, g roughness, b metallic (glTF's channel order).
    pub orm: Texture,
}

impl MaterialTextures {
    /// A material's textures from level-0 images of [`TEXTURE_SIZE`]² RGBA8 texels each (base
    /// colour sRGB, normal, occlusion-roughness-metallic), mip chains generated.
    pub fn new(base: Vec<u8>, normal: Vec<u8>, orm: Vec<u8>) -> Result<Self, String> {
        let n = TEXTURE_SIZE;
        let expected = (4 * n * n) as usize;
        for (name, image) in [("base", &base), ("normal", &normal), ("orm", &orm)] {
            if image.len() != expected {
                return Err(format!(
                    "{name} texture has {} bytes, not {n}² RGBA8 ({expected})",
                    image.len()
                ));
            }
        }
        Ok(Self::with_mips(base, normal, orm))
    }

    /// `new` for images known to be the right size.
    fn with_mips(base: Vec<u8>, normal: Vec<u8>, orm: Vec<u8>) -> Self {
        let n = TEXTURE_SIZE;
        MaterialTextures {
            base: with_mips(n, base, Channel::Srgb),
            normal: with_mips(n, normal, Channel::Normal),
            orm: with_mips(n, orm, Channel::Linear),
        }
    }
}

/// What a pattern says at one point of its tile.
struct Sample {
    color: Vec3,
    height: f32,
    occlusion: f32,
    roughness: f32,
    metallic: f32,
}

/// Generates `pattern`'s textures.
pub fn generate(pattern: Pattern) -> MaterialTextures {
    let n = TEXTURE_SIZE;
    let samples: Vec<Sample> = (0..n * n)
        .map(|i| {
            let uv = Vec2::new((i % n) as f32 / n as f32, (i / n) as f32 / n as f32);
            sample(pattern, uv)
        })
        .collect();
    let at = |x: u32, y: u32| &samples[((y % n) * n + (x % n)) as usize];
    let mut base = Vec::with_capacity((4 * n * n) as usize);
    let mut normal = Vec::with_capacity((4 * n * n) as usize);
    let mut orm = Vec::with_capacity((4 * n * n) as usize);
    // Height in texels' units: how strongly relief bends the normal.
    let strength = 6.0;
    for y in 0..n {
        for x in 0..n {
            let s = at(x, y);
            base.extend(s.color.to_array().map(encode_srgb));
            base.push(255);
            let dx = at(x + 1, y).height - at(x + n - 1, y).height;
            let dy = at(x, y + 1).height - at(x, y + n - 1).height;
            let nrm = Vec3::new(-strength * dx, -strength * dy, 1.0).normalize();
            normal.extend((nrm * 0.5 + 0.5).to_array().map(unorm8));
            normal.push(255);
            orm.extend([s.occlusion, s.roughness, s.metallic, 1.0].map(unorm8));
        }
    }
    MaterialTextures::with_mips(base, normal, orm)
}

fn sample(pattern: Pattern, uv: Vec2) -> Sample {
    let detail = fbm(uv, 16, 4, pattern as u32);
    match pattern {
        Pattern::Stone => {
            // Four courses per tile, two blocks per course, every other course offset.
            let row = (uv.y * 4.0).floor();
            let u = uv.x * 2.0 + 0.5 * (row % 2.0);
            let (bx, by) = (u.fract(), (uv.y * 4.0).fract());
            let edge = bx.min(1.0 - bx).min(by.min(1.0 - by) * 0.5);
            let mortar = edge < 0.025;
            let block = hash2(u.floor() as u32 % 2, row as u32, 17);
            let tone = 0.8 + 0.25 * block + 0.25 * (detail - 0.5);
            Sample {
                color: if mortar {
                    Vec3::new(0.5, 0.48, 0.45) * (0.9 + 0.2 * detail)
                } else {
                    Vec3::new(0.74, 0.64, 0.5) * tone
                },
                height: if mortar {
                    0.0
                } else {
                    0.6 + 0.4 * (edge * 8.0).min(1.0) * (0.7 + 0.3 * detail)
                },
                occlusion: if mortar { 0.6 } else { 1.0 },
                roughness: 0.85 + 0.1 * detail,
                metallic: 0.0,
            }
        }
        Pattern::Marble => {
            let (tx, ty) = ((uv.x * 2.0).floor(), (uv.y * 2.0).floor());
            let (fx, fy) = ((uv.x * 2.0).fract(), (uv.y * 2.0).fract());
            let grout = fx.min(1.0 - fx).min(fy.min(1.0 - fy)) < 0.012;
            let warp = fbm(uv, 8, 5, 3);
            let vein = ((uv.x + uv.y) * std::f32::consts::TAU * 3.0 + 7.0 * warp)
                .sin()
                .abs()
                .powf(0.25);
            let dark = (tx + ty) % 2.0 == 1.0;
            let stone = if dark {
                Vec3::new(0.35, 0.33, 0.32)
            } else {
                Vec3::new(0.9, 0.88, 0.84)
            };
            Sample {
                color: if grout {
                    Vec3::splat(0.3)
                } else {
                    stone * (0.55 + 0.45 * vein)
                },
                height: if grout { 0.0 } else { 1.0 },
                occlusion: if grout { 0.5 } else { 1.0 },
                roughness: if grout { 0.8 } else { 0.15 + 0.15 * detail },
                metallic: 0.0,
            }
        }
        Pattern::Fabric => {
            let threads = 48.0 * std::f32::consts::TAU;
            let (warp, weft) = ((uv.x * threads).sin(), (uv.y * threads).sin());
            let over = if warp * weft > 0.0 {
                warp.abs()
            } else {
                weft.abs()
            };
            Sample {
                color: Vec3::splat(0.75 + 0.25 * over) * (0.9 + 0.2 * detail),
                height: over,
                occlusion: 0.7 + 0.3 * over,
                roughness: 0.95,
                metallic: 0.0,
            }
        }
        Pattern::Wood => {
            let plank = (uv.y * 4.0).floor();
            let fy = (uv.y * 4.0).fract();
            let seam = fy.min(1.0 - fy) < 0.02;
            let grain = ((uv.y * 40.0 + 6.0 * fbm(uv + plank * 0.37, 4, 3, 9)) * 3.0).fract();
            Sample {
                color: Vec3::new(0.45, 0.28, 0.15)
                    * (0.75 + 0.35 * grain)
                    * (0.85 + 0.3 * hash2(plank as u32, 0, 5)),
                height: if seam { 0.0 } else { 0.8 + 0.2 * grain },
                occlusion: if seam { 0.6 } else { 1.0 },
                roughness: 0.55 + 0.2 * grain,
                metallic: 0.0,
            }
        }
        Pattern::Bronze => {
            let tarnish = fbm(uv, 4, 5, 21);
            let scratch = ((uv.x * 3.0 + uv.y * 17.0 + 2.0 * detail) * 29.0).fract() < 0.04;
            let metal = Vec3::new(0.8, 0.55, 0.3);
            let patina = Vec3::new(0.3, 0.5, 0.4);
            let t = ((tarnish - 0.45) * 3.0).clamp(0.0, 1.0);
            Sample {
                color: metal.lerp(patina, t),
                height: if scratch { 0.3 } else { 0.5 + 0.2 * detail },
                occlusion: 1.0,
                roughness: if scratch { 0.15 } else { 0.3 + 0.4 * t },
                metallic: 1.0 - 0.8 * t,
            }
        }
        Pattern::Plaster => Sample {
            color: Vec3::new(0.86, 0.83, 0.77) * (0.88 + 0.2 * detail),
            height: detail,
            occlusion: 0.85 + 0.15 * detail,
            roughness: 0.9,
            metallic: 0.0,
        },
    }
}

/// A deterministic hash of a lattice point to 0..1.
fn hash2(x: u32, y: u32, seed: u32) -> f32 {
    let mut h =
        x.wrapping_mul(0x8DA6_B343) ^ y.wrapping_mul(0xD816_3841) ^ seed.wrapping_mul(0xCB1A_B31F);
    h ^= h >> 13;
    h = h.wrapping_mul(0x5BD1_E995);
    h ^= h >> 15;
    (h & 0xFFFF) as f32 / 65535.0
}

/// Value noise with `period` lattice cells across the tile (so it tiles), smoothly
/// interpolated.
fn value_noise(uv: Vec2, period: u32, seed: u32) -> f32 {
    let p = uv * period as f32;
    let (x0, y0) = (p.x.floor(), p.y.floor());
    let (fx, fy) = (p.x - x0, p.y - y0);
    let wrap = |v: f32| (v as i64).rem_euclid(period as i64) as u32;
    let (x0, y0) = (wrap(x0), wrap(y0));
    let (x1, y1) = ((x0 + 1) % period, (y0 + 1) % period);
    let smooth = |t: f32| t * t * (3.0 - 2.0 * t);
    let (sx, sy) = (smooth(fx), smooth(fy));
    let top = hash2(x0, y0, seed) * (1.0 - sx) + hash2(x1, y0, seed) * sx;
    let bottom = hash2(x0, y1, seed) * (1.0 - sx) + hash2(x1, y1, seed) * sx;
    top * (1.0 - sy) + bottom * sy
}

/// Fractal noise: `octaves` of value noise from `period` cells, each twice as fine and half as
/// strong; 0..1.
fn fbm(uv: Vec2, period: u32, octaves: u32, seed: u32) -> f32 {
    let (mut sum, mut weight, mut total) = (0.0, 1.0, 0.0);
    for o in 0..octaves {
        sum += weight * value_noise(uv, period << o, seed + o);
        total += weight;
        weight *= 0.5;
    }
    sum / total
}

pub(super) fn unorm8(v: f32) -> u8 {
    (v.clamp(0.0, 1.0) * 255.0).round() as u8
}

pub(crate) fn encode_srgb(linear: f32) -> u8 {
    let l = linear.clamp(0.0, 1.0);
    let c = if l <= 0.003_130_8 {
        12.92 * l
    } else {
        1.055 * l.powf(1.0 / 2.4) - 0.055
    };
    unorm8(c)
}

fn decode_srgb(v: u8) -> f32 {
    let c = v as f32 / 255.0;
    if c <= 0.040_45 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

/// How a texture's texels average into the next mip level.
#[derive(Clone, Copy)]
enum Channel {
    /// Averaged in linear light.
    Srgb,
    /// Averaged as vectors, renormalised; alpha keeps the mean's length (1 at level 0).
    Normal,
    Linear,
}

/// `level0` and its mip chain down to 1×1, each level the 2×2 box average of the one above.
fn with_mips(size: u32, mut level0: Vec<u8>, channel: Channel) -> Texture {
    if let Channel::Normal = channel {
        // Each level-0 normal is a unit vector, whatever the image's own alpha said.
        level0.iter_mut().skip(3).step_by(4).for_each(|a| *a = 255);
    }
    let mut levels = vec![level0];
    let mut side = size;
    while side > 1 {
        let above = levels.last().expect("level 0 exists");
        let half = side / 2;
        let mut next = Vec::with_capacity((4 * half * half) as usize);
        for y in 0..half {
            for x in 0..half {
                let texel = |dx: u32, dy: u32, c: usize| {
                    above[(((2 * y + dy) * side + 2 * x + dx) * 4) as usize + c]
                };
                if let Channel::Normal = channel {
                    next.extend(mean_normal(
                        [(0, 0), (1, 0), (0, 1), (1, 1)]
                            .map(|(dx, dy)| [0, 1, 2, 3].map(|c| texel(dx, dy, c))),
                    ));
                    continue;
                }
                let mut rgb = [0.0f32; 3];
                for (dx, dy) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
                    for (c, sum) in rgb.iter_mut().enumerate() {
                        *sum += 0.25
                            * match channel {
                                Channel::Srgb => decode_srgb(texel(dx, dy, c)),
                                Channel::Linear | Channel::Normal => {
                                    texel(dx, dy, c) as f32 / 255.0
                                }
                            };
                    }
                }
                let out = match channel {
                    Channel::Srgb => rgb.map(encode_srgb),
                    Channel::Linear | Channel::Normal => rgb.map(unorm8),
                };
                next.extend(out);
                // Alpha (an alpha mask's coverage) averages linearly.
                let alpha: u32 = [(0, 0), (1, 0), (0, 1), (1, 1)]
                    .map(|(dx, dy)| texel(dx, dy, 3) as u32)
                    .iter()
                    .sum();
                next.push(((alpha + 2) / 4) as u8);
            }
        }
        levels.push(next);
        side = half;
    }
    Texture { size, levels }
}

/// The next level's normal texel from four (RGBA8, the direction as `xyz · 0.5 + 0.5`, alpha
/// the length of the mean it stands for): the mean of the vectors they stand for, its
/// direction renormalised and its length kept in alpha. A length below 1 is the spread of the
/// level-0 normals under the texel (Toksvig 2005).
fn mean_normal(texels: [[u8; 4]; 4]) -> [u8; 4] {
    let mean = texels
        .iter()
        .map(|t| {
            let direction = Vec3::from([t[0], t[1], t[2]].map(|c| c as f32 / 255.0 * 2.0 - 1.0));
            direction.normalize_or(Vec3::Z) * (t[3] as f32 / 255.0)
        })
        .sum::<Vec3>()
        / 4.0;
    let n = mean.normalize_or(Vec3::Z);
    let [x, y, z] = (n * 0.5 + 0.5).to_array().map(unorm8);
    [x, y, z, unorm8(mean.length().min(1.0))]
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every pattern yields three full mip chains whose coarsest level is the mean of the
    /// finest (box filtering keeps the average), and tiles: the noise wraps at the edge.
    #[test]
    fn textures_have_full_mip_chains_and_tile() {
        for pattern in [Pattern::Stone, Pattern::Plaster] {
            let t = generate(pattern);
            for tex in [&t.base, &t.normal, &t.orm] {
                assert_eq!(tex.levels.len(), TEXTURE_SIZE.trailing_zeros() as usize + 1);
                assert_eq!(tex.levels.last().unwrap().len(), 4);
            }
            let mean = |level: &[u8]| {
                level.chunks_exact(4).map(|p| p[1] as f64).sum::<f64>() / (level.len() / 4) as f64
            };
            let orm = &t.orm.levels;
            assert!((mean(&orm[0]) - mean(orm.last().unwrap())).abs() < 2.0);
        }
        let a = value_noise(Vec2::new(0.0, 0.3), 8, 1);
        let b = value_noise(Vec2::new(1.0, 0.3), 8, 1);
        assert!((a - b).abs() < 1e-6, "noise wraps at the tile's edge");
    }

    /// The normal map's alpha is the mean normal's length: 1 where the normals agree, shorter
    /// where they diverge, as Toksvig's measure of their spread. Checked against the mean in
    /// `f64` of the level-0 normals each texel covers; it breaks if a level averages the
    /// renormalised texels above it rather than the vectors they stand for.
    #[test]
    fn the_normal_maps_alpha_keeps_the_mean_normals_length() {
        let tilted = |x: u32, y: u32| {
            let (sx, sy) = (x.is_multiple_of(2), (x / 2 + y).is_multiple_of(3));
            let n = Vec3::new(if sx { 0.6 } else { -0.6 }, if sy { 0.3 } else { 0.0 }, 0.8);
            n.normalize()
        };
        let side = 8u32;
        let mut level0 = Vec::new();
        for y in 0..side {
            for x in 0..side {
                level0.extend((tilted(x, y) * 0.5 + 0.5).to_array().map(unorm8));
                level0.push(0); // an image's own alpha is ignored
            }
        }
        let t = with_mips(side, level0, Channel::Normal);
        for (level, texels) in t.levels.iter().enumerate() {
            let step = 1u32 << level;
            for (i, texel) in texels.chunks_exact(4).enumerate() {
                let (tx, ty) = (i as u32 % (side / step), i as u32 / (side / step));
                let mut mean = glam::DVec3::ZERO;
                for y in ty * step..(ty + 1) * step {
                    for x in tx * step..(tx + 1) * step {
                        mean += tilted(x, y).as_dvec3() / (step * step) as f64;
                    }
                }
                let alpha = texel[3] as f64 / 255.0;
                assert!(
                    (alpha - mean.length()).abs() < 0.02,
                    "level {level} texel {i}: {alpha} against {}",
                    mean.length()
                );
            }
        }
        assert_eq!(t.levels[0][3], 255, "level 0 holds unit normals");
        assert!(
            t.levels.last().unwrap()[3] < 230,
            "diverging normals shorten the mean"
        );
    }
}
